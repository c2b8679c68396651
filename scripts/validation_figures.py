#!/usr/bin/env python3
"""The "today" column of docs/validation.md's Summary table, from the figures the tests record.

The test that checks a row writes the row's measured figure with the `fdem-figures` crate
(`fdem_figures::record(ROW, text)`, or `record_part(ROW, PART, text)` for a row measured by
several tests) into one file per row, `<row>.txt` or `<row>.<part>.txt`, in the figures
folder: $FDEM_FIGURES_DIR when set, otherwise `validation-figures` in the target folder
($CARGO_TARGET_DIR, otherwise `target` in the repository root; a relative path is taken from
the repository root). A row is named by its `#` number.

    python3 scripts/validation_figures.py clear     # empty the figures folder
    python3 scripts/validation_figures.py render    # rewrite the column from the figures
    python3 scripts/validation_figures.py --check   # exit 1, naming each stale or missing row

`scripts/test.sh` empties the folder, runs the Rust tests, then checks. Every row of the table
must be recorded by the run, except the rows listed below in HAND_WRITTEN (measured outside
the Rust tests), whose cell is written by hand and left as it is, and the parts in OPTIONAL (recorded only by a test that the
test command does not run, `#[ignore]`d): those are checked when recorded and otherwise keep
their text. Uses the Python 3 standard library only.
"""

import os
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "validation.md"

# Rows whose figure is made of several parts, each recorded by its own test (row: number of
# parts); the parts are shown in order, joined by "; ".
PARTS = {
    12: 4, 14: 2, 17: 6, 18: 2, 40: 2, 43: 2, 47: 5, 54: 3, 62: 2, 68: 3, 70: 2, 77: 2,
    82: 4, 83: 3, 87: 4, 92: 2, 93: 2, 100: 3, 104: 2, 111: 2, 114: 2, 121: 2, 122: 2,
    123: 3, 132: 3, 136: 2, 137: 2, 139: 2, 140: 3, 143: 4, 145: 2, 146: 3, 147: 3,
    150: 6,
}

# Parts recorded only by a test that `scripts/test.sh` does not run: (row, part): reason.
OPTIONAL = {
    (70, 2): "tests/cracks.rs: `griffith_fine_mesh` is #[ignore]d (about 45 s); "
    "`cargo test --release --test all -- cracks::griffith_fine --ignored` records it",
}

# Rows whose figure is not recorded by a Rust test of the test command: row: reason.
HAND_WRITTEN = {
    49: "measured by tests/python/vtu_readback.py, not a Rust test",
    50: "measured by tests/python/mesh_counts.sh, not a Rust test",
    124: "measured by tests/mpi/mpi_runs.sh, not a Rust test",
}

SEPARATOR = "; "
FILE = re.compile(r"^(\d+)(?:\.(\d+))?\.txt$")


def figures_dir():
    def from_root(p):
        p = Path(p)
        return p if p.is_absolute() else ROOT / p

    if os.environ.get("FDEM_FIGURES_DIR"):
        return from_root(os.environ["FDEM_FIGURES_DIR"])
    return from_root(os.environ.get("CARGO_TARGET_DIR") or "target") / "validation-figures"


def split_cells(line):
    """The cells of a table line, split at the `|` not escaped as `\\|`."""
    cells, cur, i = [], "", 0
    body = line.strip()
    assert body.startswith("|") and body.endswith("|"), line
    body = body[1:-1]
    while i < len(body):
        if body[i] == "\\" and i + 1 < len(body) and body[i + 1] == "|":
            cur += "\\|"
            i += 2
            continue
        if body[i] == "|":
            cells.append(cur)
            cur = ""
        else:
            cur += body[i]
        i += 1
    cells.append(cur)
    return [c.strip() for c in cells]


def summary_rows(lines):
    """(line index, row number, cells) of every row of the Summary table."""
    start = lines.index("## Summary")
    rows, in_table = [], False
    for i in range(start + 1, len(lines)):
        line = lines[i]
        if line.startswith("|"):
            in_table = True
            cells = split_cells(line)
            if cells[0].isdigit():
                assert len(cells) == 6, f"docs/validation.md:{i + 1}: {len(cells)} cells, not 6"
                rows.append((i, int(cells[0]), cells))
        elif in_table:
            break
    return rows


def read_figures(folder):
    """{row: {part: text}} (part 0: the whole row) and the names of unexpected files."""
    figures, strays = {}, []
    if folder.is_dir():
        for f in sorted(folder.iterdir()):
            if f.name.startswith("."):
                continue
            m = FILE.match(f.name)
            if not m:
                strays.append(f.name)
                continue
            row, part = int(m.group(1)), int(m.group(2) or 0)
            text = f.read_text(encoding="utf-8").strip()
            figures.setdefault(row, {})[part] = text.replace("|", "\\|")
    return figures, strays


def expected(row, recorded, old):
    """The row's cell from its recorded figure, or (None, [what is missing])."""
    n = PARTS.get(row)
    if n is None:
        if set(recorded) - {0}:
            return None, [f"parts {sorted(set(recorded) - {0})} recorded, the row has none"]
        return (recorded[0], []) if 0 in recorded else (None, ["not recorded"])
    if 0 in recorded or set(recorded) - set(range(1, n + 1)):
        return None, [f"recorded as {sorted(recorded)}, the row has parts 1..{n}"]
    old_parts = old.split(SEPARATOR)
    parts, missing = [], []
    for p in range(1, n + 1):
        if p in recorded:
            parts.append(recorded[p])
        elif (row, p) in OPTIONAL and len(old_parts) == n:
            parts.append(old_parts[p - 1])
        else:
            missing.append(f"part {p} not recorded")
    return (SEPARATOR.join(parts), []) if not missing else (None, missing)


def main(argv):
    if argv not in (["render"], ["--check"], ["clear"]):
        print(__doc__.split("\n\n")[2], file=sys.stderr)
        return 2
    folder = figures_dir()
    if argv == ["clear"]:
        if folder.is_dir():
            for f in folder.iterdir():
                f.unlink()
        return 0
    lines = DOC.read_text(encoding="utf-8").split("\n")
    rows = summary_rows(lines)
    numbers = [r for _, r, _ in rows]
    figures, strays = read_figures(folder)
    problems = [f"{folder / s}: not a figure file (<row>.txt or <row>.<part>.txt)" for s in strays]
    if len(set(numbers)) != len(numbers):
        problems.append("docs/validation.md: a row number appears twice in the Summary table")
    listed = set(HAND_WRITTEN) | set(PARTS) | {r for r, _ in OPTIONAL}
    for r in sorted(listed - set(numbers)):
        problems.append(f"row {r}: listed in scripts/validation_figures.py, not in the table")
    for r in sorted(set(figures) - set(numbers)):
        problems.append(f"row {r}: recorded, but the table has no such row")

    changed = 0
    for i, row, cells in rows:
        if row in HAND_WRITTEN:
            if row in figures:
                problems.append(
                    f"row {row}: recorded, but listed as hand-written"
                    " in scripts/validation_figures.py (remove it from the list)"
                )
            continue
        text, missing = expected(row, figures.get(row, {}), cells[4])
        if text is None:
            problems.extend(f"row {row}: {m}" for m in missing)
            continue
        if text != cells[4]:
            changed += 1
            if argv == ["--check"]:
                problems.append(f"row {row}: stale: the table says {cells[4]!r}, the test measured {text!r}")
            else:
                cells[4] = text
                lines[i] = "| " + " | ".join(cells) + " |"

    if argv == ["render"] and changed:
        DOC.write_text("\n".join(lines), encoding="utf-8")
    for p in problems:
        print(f"validation figures: {p}", file=sys.stderr)
    if problems:
        print(
            f"validation figures: {len(problems)} problem(s) (figures from {folder}); "
            "run `bash scripts/test.sh`, then `python3 scripts/validation_figures.py render`",
            file=sys.stderr,
        )
        return 1
    verb = "rewrote" if argv == ["render"] else "checked"
    n = len(rows) - len(HAND_WRITTEN)
    print(f"validation figures: {verb} docs/validation.md ({n} recorded rows, {changed} changed)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
