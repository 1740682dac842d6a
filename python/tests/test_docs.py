"""docs/python.md's worked example runs and prints what the page says."""

import contextlib
import io
import re

from conftest import REPO


def blocks(kind: str, text: str):
    """The fenced blocks of one kind, in order."""
    return re.findall(r"```" + kind + r"\n(.*?)```", text, re.S)


def test_the_worked_example_prints_what_the_page_shows(monkeypatch):
    monkeypatch.delenv("ADDIPOS_TARGET", raising=False)
    monkeypatch.delenv("ADDIPOS_RECORD", raising=False)
    page = (REPO / "docs" / "python.md").read_text()
    section = page.split("## The worked example", 1)[1].split("\n## ", 1)[0]
    example = blocks("python", section)[0]
    shown = blocks("text", section)[0]
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(example, "docs/python.md", "exec"), {})
    assert out.getvalue() == shown
