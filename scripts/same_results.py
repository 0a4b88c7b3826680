#!/usr/bin/env python3
"""Are two result directories the same apart from wall-clock times? For refactors.

    python3 scripts/same_results.py results/ /tmp/new/

Compares every file of either directory (recursively):
- `*.json`: parsed and compared key by key, without `timing`, `batch.input_hash` (it mixes in
  the program's source hash) and the sizes and hashes that `batch.files` lists for the pages
  that print times (`.md`, `.html`);
- `*.md`, `*.html`: text, with the times they print masked ("solve 0.040 ms, total 0.049 ms";
  the last cell of a summary row, its time in ms);
- `summary.csv`: without its `time_s` and `input_hash` columns;
- everything else (SVG, DXF, CSV): byte for byte.
Prints one line per difference (the first differing keys of a JSON file) and exits 1 if there
is any, 0 otherwise.
"""
import csv
import io
import json
import pathlib
import re
import sys

TIME = re.compile(r"\d+(?:\.\d+)?(?:e-?\d+)? ?(?:ms|µs|s)\b")
PAGE = (".md", ".html")


# The last cell of a summary row is the machine's time in ms: in `summary.md` a Markdown
# table row, in `index.html` the row's last <td>.
LAST_MD_CELL = re.compile(r"\| [0-9.]+ \|$", re.M)
LAST_TD = re.compile(r"<td>[0-9.]+</td>(\s*</tr>)")


def mask_text(text):
    text = LAST_MD_CELL.sub("| <time> |", text)
    text = LAST_TD.sub(r"<td><time></td>\1", text)
    return TIME.sub("<time>", text)


def json_diffs(a, b, path=""):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if path == "" and k == "timing":
                continue
            if k not in a or k not in b:
                yield f"{path}{k}: only in {'new' if k in b else 'old'}"
                continue
            yield from json_diffs(a[k], b[k], f"{path}{k}.")
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            yield f"{path[:-1]}: length {len(a)} != {len(b)}"
        for i, (x, y) in enumerate(zip(a, b)):
            yield from json_diffs(x, y, f"{path}{i}.")
    elif a != b:
        yield f"{path[:-1]}: {a!r} != {b!r}"


def strip_manifest(doc):
    batch = doc.get("batch") if isinstance(doc, dict) else None
    if isinstance(batch, dict):
        batch.pop("input_hash", None)  # mixes in the program's source hash
        for name, f in batch.get("files", {}).items():
            if name.endswith(PAGE) and isinstance(f, dict):
                f.pop("bytes", None)
                f.pop("hash", None)
    return doc


def summary_rows(text):
    rows = list(csv.reader(io.StringIO(text)))
    drop = [i for i, c in enumerate(rows[0] if rows else []) if c in ("time_s", "input_hash")]
    return [[c for i, c in enumerate(r) if i not in drop] for r in rows]


def compare(old, new, rel):
    if rel.suffix == ".json":
        a = strip_manifest(json.loads(old.read_text()))
        b = strip_manifest(json.loads(new.read_text()))
        return [f"{rel}: {d}" for d in list(json_diffs(a, b))[:8]]
    if rel.name == "summary.csv":
        ok = summary_rows(old.read_text()) == summary_rows(new.read_text())
    elif rel.suffix in PAGE:
        ok = mask_text(old.read_text()) == mask_text(new.read_text())
    else:
        ok = old.read_bytes() == new.read_bytes()
    return [] if ok else [f"{rel}: differs"]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    old, new = (pathlib.Path(p) for p in sys.argv[1:])
    names = {p.relative_to(old) for p in old.rglob("*") if p.is_file()}
    names |= {p.relative_to(new) for p in new.rglob("*") if p.is_file()}
    diffs = []
    for rel in sorted(names):
        if rel.name.startswith("."):
            continue
        if not (old / rel).exists() or not (new / rel).exists():
            diffs.append(f"{rel}: only in {'new' if (new / rel).exists() else 'old'}")
            continue
        diffs += compare(old / rel, new / rel, rel)
    for d in diffs:
        print(d)
    print(f"{len(names)} files, {len(diffs)} differences")
    sys.exit(1 if diffs else 0)


if __name__ == "__main__":
    main()
