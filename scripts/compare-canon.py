#!/usr/bin/env python3
"""Compare two streams of canonical motion calls: LinuxCNC rs274's and latheguard's.

Usage:
    scripts/compare-canon.py [--tol 1e-4] [--show 10] [--skip-null] REF OURS
    scripts/rs274-ref.sh -g p.ngc > ref.txt
    latheguard moves p.ngc --format canon > ours.txt
    scripts/compare-canon.py ref.txt ours.txt
(either file may be `-` for standard input). Python 3 standard library only.

What is compared: only the three motion calls
    STRAIGHT_TRAVERSE(x, y, z, a, b, c)
    STRAIGHT_FEED(x, y, z, a, b, c)
    ARC_FEED(first_end, second_end, first_center, second_center, rotation, axis_end, a, b, c)
in order, call by call. Every other line is dropped: rs274's set-up calls before the program's
first move (USE_LENGTH_UNITS, SET_G5X_OFFSET, SET_G92_OFFSET, SET_XY_ROTATION,
SET_FEED_REFERENCE, ON_RESET, SELECT_PLANE, ...), SET_FEED_RATE, spindle, tool, COMMENT and
program-end calls, the "executing" line rs274 writes to stderr, error messages, (PRINT,...)
output. A line counts only when the call name comes first on it, after an optional output
counter (rs274's `%5d ` column) and an optional N column (`N..... `, or `N<digits>` padded to 6
characters, with no space at all when the N number has 6 or more digits); so `rs274 -g` output
as is, the corpus `expected` files (counter stripped by awk) and bare call lines all parse.
A COMMENT("... STRAIGHT_FEED(...) ...") is never taken for a move.

Numbers are compared with an absolute tolerance (default 1e-4; rs274 prints 4 decimals, so
values are already rounded to 5e-5); ARC_FEED's rotation (turn count and direction: 1 for G3,
-1 for G2 in every plane, +-(n+1) for P n extra turns) must be equal exactly.

Conventions of rs274's numbers, which our canon output must follow to compare equal:
  * positions are in the program's current length unit (inch after G20), in program
    coordinates: G5x / G92 offsets and tool length offsets are NOT applied (they are separate
    SET_G5X_OFFSET / SET_G92_OFFSET / USE_TOOL_LENGTH_OFFSET calls);
  * X is always a radius: in G7 (diameter mode) X20 is printed as 10.0000; arc I is a radius
    in both G7 and G8;
  * in G18 (the lathe's XZ plane) ARC_FEED's first coordinate is Z and the second is X:
    ARC_FEED(z_end, x_end, z_center, x_center, rotation, y_end, a, b, c), rotation -1 for G2;
  * rs274 starts at X0 Y0 Z0 with no INI file, and emits a move even when it goes nowhere
    (a G0 to the current position, the repeated start traverses of G7x cycles); use
    --skip-null to drop zero-length STRAIGHT_* moves from both sides if ours omits them.

Exit status: 0 when the sequences agree, 1 on any mismatch (including different lengths),
2 on bad usage or an unreadable file.
"""

import argparse
import re
import sys

MOVE_RE = re.compile(
    r"^\s*(?:\d+\s+)?"  # rs274's output counter, if not stripped
    r"(?:N(?:\.{5}|\d+)\s*)?"  # rs274's N column
    r"(STRAIGHT_TRAVERSE|STRAIGHT_FEED|ARC_FEED)\((.*)\)\s*$"
)

ARG_NAMES = {
    "STRAIGHT_TRAVERSE": ["x", "y", "z", "a", "b", "c"],
    "STRAIGHT_FEED": ["x", "y", "z", "a", "b", "c"],
    "ARC_FEED": [
        "first_end(Z in G18)",
        "second_end(X in G18)",
        "first_center(Z in G18)",
        "second_center(X in G18)",
        "rotation",
        "axis_end(Y in G18)",
        "a",
        "b",
        "c",
    ],
}
ROTATION_INDEX = 4


class Move:
    __slots__ = ("kind", "args", "line", "text")

    def __init__(self, kind, args, line, text):
        self.kind = kind
        self.args = args
        self.line = line
        self.text = text


def read_moves(path):
    """Returns (moves, problems); problems are lines that look like moves but do not parse."""
    moves, problems = [], []
    f = sys.stdin if path == "-" else open(path, encoding="utf-8", errors="replace")
    with f:
        for lineno, raw in enumerate(f, 1):
            m = MOVE_RE.match(raw)
            if not m:
                continue
            kind = m.group(1)
            try:
                args = [float(v) for v in m.group(2).split(",")]
            except ValueError:
                problems.append((lineno, raw.rstrip("\n")))
                continue
            moves.append(Move(kind, args, lineno, raw.strip()))
    return moves, problems


def drop_null(moves, tol):
    """Drops STRAIGHT_* moves that do not change the position (x, y, z, a, b, c).

    The position after an ARC_FEED is taken in G18 order (first = Z, second = X, axis = Y)."""
    out, pos = [], None
    for mv in moves:
        if mv.kind == "ARC_FEED":
            a = mv.args
            pos = [a[1], a[5], a[0]] + a[6:9] if len(a) == 9 else None
            out.append(mv)
            continue
        if pos is not None and len(pos) == len(mv.args) and all(
            abs(p - q) <= tol for p, q in zip(pos, mv.args)
        ):
            continue
        pos = mv.args
        out.append(mv)
    return out


def differences(ref, ours, tol):
    """Returns a list of human-readable differences between two moves (empty if they agree)."""
    if ref.kind != ours.kind:
        return ["call %s vs %s" % (ref.kind, ours.kind)]
    if len(ref.args) != len(ours.args):
        return ["%d arguments vs %d" % (len(ref.args), len(ours.args))]
    diffs = []
    names = ARG_NAMES[ref.kind]
    for i, (p, q) in enumerate(zip(ref.args, ours.args)):
        name = names[i] if i < len(names) else "arg%d" % (i + 1)
        if ref.kind == "ARC_FEED" and i == ROTATION_INDEX:
            if p != q:
                diffs.append("%s %g vs %g" % (name, p, q))
        elif not abs(p - q) <= tol:  # also catches NaN
            diffs.append("%s %.6f vs %.6f (diff %.3g)" % (name, p, q, abs(p - q)))
    return diffs


def main(argv):
    ap = argparse.ArgumentParser(
        description="Compare rs274 canonical motion calls with ours (see the module docstring)."
    )
    ap.add_argument("ref", help="reference output (rs274 -g, raw or with the counter stripped)")
    ap.add_argument("ours", help="our canon output")
    ap.add_argument("--tol", type=float, default=1e-4, help="absolute tolerance (default 1e-4)")
    ap.add_argument("--show", type=int, default=10, help="mismatches to print (default 10)")
    ap.add_argument(
        "--skip-null",
        action="store_true",
        help="drop zero-length STRAIGHT_TRAVERSE/STRAIGHT_FEED moves from both sides",
    )
    args = ap.parse_args(argv)
    if args.ref == "-" and args.ours == "-":
        ap.error("only one of the inputs can be standard input")

    try:
        ref, ref_bad = read_moves(args.ref)
        ours, ours_bad = read_moves(args.ours)
    except OSError as e:
        print("compare-canon: %s" % e, file=sys.stderr)
        return 2

    for path, bad in ((args.ref, ref_bad), (args.ours, ours_bad)):
        for lineno, text in bad[: args.show]:
            print("%s:%d: unparsable move: %s" % (path, lineno, text))
    if args.skip_null:
        ref = drop_null(ref, args.tol)
        ours = drop_null(ours, args.tol)

    mismatches = 0
    first = None
    for i, (r, o) in enumerate(zip(ref, ours)):
        diffs = differences(r, o, args.tol)
        if not diffs:
            continue
        mismatches += 1
        if first is None:
            first = i + 1
        if mismatches <= args.show:
            print("move %d: ref %s:%d vs ours %s:%d: %s" % (
                i + 1, args.ref, r.line, args.ours, o.line, "; ".join(diffs)))
            print("  ref:  %s" % r.text)
            print("  ours: %s" % o.text)
    if mismatches > args.show:
        print("... %d more mismatching moves not shown" % (mismatches - args.show))

    length_differs = len(ref) != len(ours)
    if length_differs:
        n = min(len(ref), len(ours))
        longer, name = (ref, "ref") if len(ref) > len(ours) else (ours, "ours")
        extra = longer[n]
        print("length: ref has %d moves, ours %d; first extra move in %s at line %d: %s" % (
            len(ref), len(ours), name, extra.line, extra.text))

    bad_lines = len(ref_bad) + len(ours_bad)
    ok = mismatches == 0 and not length_differs and bad_lines == 0
    summary = "compare-canon: %s: %d ref moves, %d our moves, %d compared, %d mismatching" % (
        "OK" if ok else "MISMATCH", len(ref), len(ours), min(len(ref), len(ours)), mismatches)
    if first is not None:
        summary += " (first at move %d)" % first
    if bad_lines:
        summary += ", %d unparsable move lines" % bad_lines
    summary += ", tol %g%s" % (args.tol, ", null moves skipped" if args.skip_null else "")
    print(summary)
    return 0 if ok else 1


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except BrokenPipeError:
        sys.exit(1)
