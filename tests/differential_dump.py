#!/usr/bin/env python3
"""Differential dump: the trace corpus and N random NC programs run by two
builds of `addipos`; every answer, spooled element and error compared.

Usage: python3 tests/differential_dump.py OLD_BINARY NEW_BINARY [N] [SEED] [CORPUS]

Run by hand around a structural change (docs/architecture.md,
"Architecture checks"), not by CI: it needs the build from before.

For each random program both builds run `addipos run --trace`, and the
printed output, the exit status, stderr and the written trace must be the
same bytes; for the corpus `addipos replay -v traces/` must print the same
bytes. Prints a summary and every difference (at most about 20); exits
1 if there is any."""
import os, random, subprocess, sys, tempfile

def program(rng):
    lines = ["%dump", "N1 G00 X0 Y0 Z0 G17"]
    n = 2
    r = rng.choice([0.5, 1, 2, 3.5, 5])
    lines.append(f"N{n} V.G.WZ_AKT.R={r}"); n += 1
    lines.append(f"N{n} {rng.choice(['G25', 'G26'])} {rng.choice(['G138', 'G237', 'G238', 'G239', ''])}"); n += 1
    x, y = rng.uniform(-50, 50), rng.uniform(-50, 50)
    lines.append(f"N{n} G01 X{x:.3f} Y{y:.3f} F1000"); n += 1
    lines.append(f"N{n} {rng.choice(['G41', 'G42'])}"); n += 1
    for _ in range(rng.randint(1, 12)):
        nx, ny = rng.uniform(-100, 100), rng.uniform(-100, 100)
        kind = rng.random()
        if kind < 0.6:
            lines.append(f"N{n} G01 X{nx:.3f} Y{ny:.3f}")
        else:
            g = rng.choice(["G02", "G03"])
            if kind < 0.8:
                rad = abs(rng.uniform(10, 150))
                lines.append(f"N{n} {g} X{nx:.3f} Y{ny:.3f} R{rad:.3f}")
            else:
                # centre on the chord's bisector: a consistent arc
                mx, my = (x + nx) / 2, (y + ny) / 2
                dx, dy = ny - y, -(nx - x)
                t = rng.uniform(-1, 1)
                cx, cy = mx + t * dx, my + t * dy
                lines.append(f"N{n} {g} X{nx:.3f} Y{ny:.3f} I{cx - x:.3f} J{cy - y:.3f}")
        x, y = nx, ny
        n += 1
    lines.append(f"N{n} G40 G01 X{x + rng.uniform(-20, 20):.3f} Y{y + rng.uniform(-20, 20):.3f}"); n += 1
    lines.append(f"N{n} M30")
    return "\n".join(lines) + "\n"

def run(binary, prog, work, tag):
    trace = os.path.join(work, f"{tag}.trace")
    p = subprocess.run([binary, "run", "--trace", trace, prog], capture_output=True, timeout=60)
    body = open(trace, "rb").read() if os.path.exists(trace) else b""
    if os.path.exists(trace):
        os.remove(trace)
    return p.returncode, p.stdout, p.stderr, body

def main():
    old, new = sys.argv[1], sys.argv[2]
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 3000
    seed = int(sys.argv[4]) if len(sys.argv) > 4 else 7
    corpus = sys.argv[5] if len(sys.argv) > 5 else "traces"
    a = subprocess.run([old, "replay", "-v", corpus], capture_output=True)
    b = subprocess.run([new, "replay", "-v", corpus], capture_output=True)
    diffs = []
    if (a.returncode, a.stdout, a.stderr) != (b.returncode, b.stdout, b.stderr):
        diffs.append("corpus replay differs")
    rng = random.Random(seed)
    ok_runs = err_runs = elements = 0
    with tempfile.TemporaryDirectory() as work:
        for i in range(n):
            prog = os.path.join(work, f"p{i}.nc")
            open(prog, "w").write(program(rng))
            ra = run(old, prog, work, "a")
            rb = run(new, prog, work, "b")
            if ra != rb:
                diffs.append(f"program {i} differs (seed {seed}): {open(prog).read()!r}")
                if len(diffs) > 20:
                    break
            if ra[0] == 0:
                ok_runs += 1
            else:
                err_runs += 1
            elements += ra[1].count(b"\n< ")+ ra[1].startswith(b"< ")
    print(f"corpus: {'same' if not diffs or diffs[0] != 'corpus replay differs' else 'DIFFERENT'}")
    print(f"random programs: {n} ({ok_runs} ran to the end, {err_runs} stopped with an error), {elements} spooled elements, {len([d for d in diffs if d.startswith('program')])} differ")
    for d in diffs:
        print(d)
    sys.exit(1 if diffs else 0)

main()
