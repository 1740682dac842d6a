#!/usr/bin/env python3
"""Checks a wheel of the Python package before it is published
(`.ci/run` runs this on the wheel it builds; docs/python.md):

    python3 tests/wheel_check.py target/wheels/addipos-*.whl

* its tags: the stable ABI (`cp38-abi3`) on manylinux_2_17 (glibc 2.17 or
  newer: what PyPI takes and older distributions load), in the file name
  and in its WHEEL file;
* auditwheel agrees: the extension needs no symbol version newer than the
  manylinux_2_17 policy allows and links no library outside it;
* the extension is stripped (no symbol table);
* the metadata names the licence (License-Expression) and the wheel
  carries each licence file it lists (License-File).

Exit status 0 when every check holds; a failed check raises.
"""

import io
import subprocess
import sys
import zipfile
from pathlib import Path

# pyelftools, a dependency of auditwheel.
from elftools.elf.elffile import ELFFile

TAG = "manylinux_2_17_x86_64"


def check(wheel):
    name = Path(wheel).name
    assert "-cp38-abi3-" in name and TAG in name, name
    with zipfile.ZipFile(wheel) as z:
        files = z.namelist()
        info = next(f for f in files if f.endswith(".dist-info/WHEEL"))
        tags = [line.split(":", 1)[1].strip() for line in z.read(info).decode().splitlines()
                if line.startswith("Tag:")]
        assert f"cp38-abi3-{TAG}" in tags, tags
        meta = z.read(info.replace("/WHEEL", "/METADATA")).decode().splitlines()
        assert "License-Expression: MIT OR Apache-2.0" in meta, meta
        licences = [line.split(":", 1)[1].strip() for line in meta
                    if line.startswith("License-File:")]
        assert licences, meta
        for lic in licences:
            assert any(f.endswith(f".dist-info/licenses/{lic}") for f in files), (lic, files)
        (so,) = [f for f in files if f.endswith(".so")]
        elf = ELFFile(io.BytesIO(z.read(so)))
        assert elf.get_section_by_name(".symtab") is None, f"{so} is not stripped"
    shown = subprocess.run([sys.executable, "-m", "auditwheel", "show", wheel],
                           capture_output=True, text=True, check=True).stdout
    assert f'consistent with the following platform tag:\n"{TAG}"' in shown, shown
    print(f"ok: {name}: {', '.join(tags)}; stripped; licences {', '.join(licences)}")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: wheel_check.py WHEEL...")
    for w in sys.argv[1:]:
        check(w)
