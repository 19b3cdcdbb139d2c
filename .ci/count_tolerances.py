#!/usr/bin/env python3
"""Count literal tolerances in src/: exponent literals with a negative exponent (`1e-9`,
`2.5e-12`) on code lines, outside comments, `const` definitions and `#[cfg(test)]` modules;
and the uses of `tol::`. A literal whose line (or the line above) carries a comment with
`not a tolerance`, or that follows a comment with `not tolerance literals` in the same block,
is counted apart (the comment says why). `--list` prints every counted literal as path:line: text, `--exempt` the ones counted apart.

    python3 .ci/count_tolerances.py [--list] [--exempt] [--max N]

With `--max N` the script fails (exit 1) when more than N literals are counted.
"""
import pathlib
import re
import sys

LIT = re.compile(r"(?<![\w.])\d+(?:\.\d+)?(?:_?\d)*e-\d+(?:_?f64)?(?![\w.])")
CONST = re.compile(r"^\s*(pub(\([^)]*\))?\s+)?(const|static)\s")


def strip_comment(line):
    # Drop a `//` comment, ignoring `//` inside a string literal (good enough for this code).
    out, in_str, i = [], False, 0
    while i < len(line):
        c = line[i]
        if c == '"' and (i == 0 or line[i - 1] != "\\"):
            in_str = not in_str
        if not in_str and line.startswith("//", i):
            break
        out.append(c)
        i += 1
    return "".join(out)


def scan(path, name):
    hits, exempt, tol_uses = [], [], 0
    lines = path.read_text().splitlines()
    depth, test_depth, pending_test, in_const = 0, None, False, False
    block_exempt = None
    for n, raw in enumerate(lines, 1):
        code = strip_comment(raw)
        stripped = code.strip()
        if raw.strip().startswith("#[cfg(test)]"):
            pending_test = True
        if test_depth is None and pending_test and stripped.startswith("mod "):
            test_depth = depth
            pending_test = False
        in_test = test_depth is not None
        if CONST.match(code):
            in_const = True
        tol_uses += 0 if in_test else code.count("tol::")
        if "not tolerance literals" in raw and block_exempt is None:
            block_exempt = depth
        if not in_test and not in_const:
            for m in LIT.finditer(code):
                note = raw + (lines[n - 2] if n > 1 else "")
                marked = "not a tolerance" in note or block_exempt is not None
                (exempt if marked else hits).append(
                    f"{name}:{n}: {raw.strip()}"
                )
        if in_const and ";" in code:
            in_const = False
        depth += code.count("{") - code.count("}")
        if test_depth is not None and depth <= test_depth and "}" in code:
            test_depth = None
        if block_exempt is not None and depth < block_exempt:
            block_exempt = None
    return hits, exempt, tol_uses


def main():
    args = sys.argv[1:]
    root = pathlib.Path(__file__).resolve().parent.parent / "src"
    hits, exempt, uses = [], [], 0
    for p in sorted(root.rglob("*.rs")):
        h, e, u = scan(p, p.relative_to(root.parent))
        hits += h
        exempt += e
        uses += u
    if "--list" in args:
        print("\n".join(hits))
    if "--exempt" in args:
        print("\n".join(exempt))
    print(f"literal tolerances: {len(hits)}; marked not a tolerance: {len(exempt)}; tol:: uses: {uses}")
    if "--max" in args:
        limit = int(args[args.index("--max") + 1])
        if len(hits) > limit:
            print(f"more than {limit} literal tolerances; name them in math::tol or a documented const")
            sys.exit(1)


if __name__ == "__main__":
    main()
