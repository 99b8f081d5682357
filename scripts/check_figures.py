#!/usr/bin/env python3
"""Every figure outside the generated pages is checked against them (issue 30, item 3).

Measurements live in pages that programs write whole: BENCHMARKS.md (bench/peers/run.sh),
docs/size.md, docs/accuracy.md, docs/trade.md, docs/drift.md, docs/walking.md. The one copy
allowed elsewhere is the README's table of headline ratios, and this script holds it to
BENCHMARKS.md. It fails (exit status 1, one line per problem) when:

1. a cell of a README table whose first header cell names a column of BENCHMARKS.md's tables
   (such as `Pinocchio / ours (v3)`) differs from that column in BENCHMARKS.md, for the model
   the row names (its first cell, as BENCHMARKS.md's `### <model> …` headings write it) and the
   output the column names (its header, as the tables' first column writes it); or the README
   has no such table;
2. the README has a ratio (`8.8×`) or a time in ns or µs outside such a table;
3. ARCHITECTURE.md, docs/README.md or a page of docs/guide/ has a ratio or a time in ns or µs
   at all (they link the generated pages instead);
4. a comment in the sources of the generator, the runtime, the reference, the macros or the CLI
   (`//`, `///`, `//!`) has a time in ns or µs (comments keep the reasons, not the timings);
5. a relative link in those pages points to a file that does not exist, or to a heading that
   the target page does not have.

`python3 scripts/check_figures.py --fix` copies the ratios from BENCHMARKS.md into the README's
table (after a new benchmark run), then checks. Standard library only; run from anywhere.
"""

import re
import sys
import unicodedata
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
BENCHMARKS = ROOT / "BENCHMARKS.md"
PROSE = [ROOT / "ARCHITECTURE.md", ROOT / "docs" / "README.md"] + sorted(
    (ROOT / "docs" / "guide").glob("*.md")
)
LINKED = [README] + PROSE
SOURCES = ["codegen/src", "runtime/src", "dynamics/src", "macros/src", "cli/src", "python/src"]

# A ratio: a number written against the sign, `8.8×` (a product of sizes is `6 × 6`).
RATIO = re.compile(r"\d×")
# A time: a number, then ns or µs.
TIMING = re.compile(r"\d(?:[\d,.]*\d)?\s?(?:ns|µs)\b")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
LINK = re.compile(r"\]\(([^)\s]+)\)")


def cells(line):
    """The cells of a Markdown table row, stripped."""
    return [c.strip() for c in line.strip().strip("|").split("|")]


def tables(lines):
    """(first line number, header cells, [(line number, cells)]) for each Markdown table."""
    found = []
    i = 0
    while i < len(lines):
        if (
            lines[i].lstrip().startswith("|")
            and i + 1 < len(lines)
            and re.fullmatch(r"\s*\|?[\s:|-]+\|?\s*", lines[i + 1])
            and "-" in lines[i + 1]
        ):
            header = cells(lines[i])
            rows = []
            j = i + 2
            while j < len(lines) and lines[j].lstrip().startswith("|"):
                rows.append((j, cells(lines[j])))
                j += 1
            found.append((i, header, rows))
            i = j
        else:
            i += 1
    return found


def benchmark_cells(lines):
    """{(model, output, column): value} from every table under a `### <model> …` heading,
    and the set of the tables' column names."""
    values = {}
    ambiguous = set()
    columns = set()
    model_at = {}
    model = None
    for n, line in enumerate(lines):
        m = HEADING.match(line)
        if m:
            words = m.group(2).split()
            model = words[0].rstrip(":") if len(m.group(1)) == 3 and words else None
        model_at[n] = model
    for start, header, rows in tables(lines):
        model = model_at[start]
        if model is None:
            continue
        columns.update(header[1:])
        for _, row in rows:
            for column, value in zip(header[1:], row[1:]):
                key = (model, row[0], column)
                if key in values and values[key] != value:
                    ambiguous.add(key)
                values.setdefault(key, value)
    for key in ambiguous:
        values[key] = None
    return values, columns


def slug(heading):
    """The anchor GitHub gives a heading."""
    text = re.sub(r"[`*_]|\[([^\]]*)\]\([^)]*\)", lambda m: m.group(1) or "", heading)
    text = text.strip().lower()
    kept = []
    for ch in text:
        if ch in " -_" or unicodedata.category(ch)[0] in "LN":
            kept.append(ch)
    return "".join(kept).replace(" ", "-")


def anchors(path):
    seen = {}
    found = set()
    in_code = False
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            in_code = not in_code
        m = None if in_code else HEADING.match(line)
        if m:
            base = slug(m.group(2))
            k = seen.get(base, 0)
            seen[base] = k + 1
            found.add(base if k == 0 else f"{base}-{k}")
    return found


def check_links(path, problems):
    in_code = False
    for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if line.startswith("```"):
            in_code = not in_code
        if in_code:
            continue
        for target in LINK.findall(line):
            if re.match(r"[a-z]+:", target):
                continue
            file, _, anchor = target.partition("#")
            dest = (path.parent / file).resolve() if file else path
            where = f"{path.relative_to(ROOT)}:{n}"
            if not dest.exists():
                problems.append(f"{where}: link to {target}: no such file")
            elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
                problems.append(f"{where}: link to {target}: no such heading")


def main():
    fix = "--fix" in sys.argv[1:]
    problems = []
    bench_lines = BENCHMARKS.read_text(encoding="utf-8").splitlines()
    values, columns = benchmark_cells(bench_lines)

    readme_lines = README.read_text(encoding="utf-8").splitlines()
    checked_lines = set()
    checked = 0
    for start, header, rows in tables(readme_lines):
        column = header[0]
        if column not in columns:
            continue
        checked_lines.update({start, start + 1} | {n for n, _ in rows})
        for n, row in rows:
            model = row[0]
            for output, got in zip(header[1:], row[1:]):
                want = values.get((model, output, column), "missing")
                where = f"README.md:{n + 1}"
                if want is None:
                    problems.append(f"{where}: {model} {output} '{column}' is ambiguous in BENCHMARKS.md")
                elif want == "missing":
                    problems.append(f"{where}: {model} {output} '{column}' is not in BENCHMARKS.md")
                elif got != want:
                    if fix:
                        row_cells = cells(readme_lines[n])
                        row_cells[header.index(output)] = want
                        readme_lines[n] = "| " + " | ".join(row_cells) + " |"
                    else:
                        problems.append(
                            f"{where}: {model} {output} '{column}' is {got}, BENCHMARKS.md says {want}"
                        )
                checked += 1
    if fix:
        README.write_text("\n".join(readme_lines) + "\n", encoding="utf-8")
    if checked == 0:
        problems.append("README.md: no table of ratios named after a BENCHMARKS.md column")

    for n, line in enumerate(readme_lines):
        if n in checked_lines:
            continue
        for pattern, what in ((RATIO, "a ratio"), (TIMING, "a time")):
            if pattern.search(line):
                problems.append(
                    f"README.md:{n + 1}: {what} outside the checked table: '{line.strip()}'"
                )

    for path in PROSE:
        for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            for pattern, what in ((RATIO, "a ratio"), (TIMING, "a time")):
                if pattern.search(line):
                    problems.append(
                        f"{path.relative_to(ROOT)}:{n}: {what} (link the generated page "
                        f"instead): '{line.strip()}'"
                    )

    for folder in SOURCES:
        for path in sorted((ROOT / folder).rglob("*.rs")):
            for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                comment = line.split("//", 1)
                if len(comment) == 2 and TIMING.search(comment[1]):
                    problems.append(
                        f"{path.relative_to(ROOT)}:{n}: a time in a comment: '{line.strip()}'"
                    )

    for path in LINKED:
        check_links(path, problems)

    for p in problems:
        print(p)
    if problems:
        print(f"check_figures: {len(problems)} problem(s)", file=sys.stderr)
        return 1
    print(f"check_figures: {checked} README figures agree with BENCHMARKS.md; no stray timings")
    return 0


if __name__ == "__main__":
    sys.exit(main())
