"""Strips the wall-time fields of rockcal's output files and prints a digest.

usage: normalise.py RUNS_DIR NORMALISED_DIR

Every file under RUNS_DIR is normalised into NORMALISED_DIR (same relative
path) and its sha256 printed as "digest  path". Dropped: JSON keys and CSV
columns naming wall time ("seconds", "wall", "elapsed"; not dt_seconds or
sample_seconds, which are simulation settings), and in Markdown and HTML the
timing text and the plot against wall time.
"""
import csv
import hashlib
import io
import json
import os
import re
import sys

KEEP = {"dt_seconds", "sample_seconds"}


def timing_key(name):
    name = str(name).lower()
    if name in KEEP:
        return False
    return any(w in name for w in ("seconds", "wall", "elapsed"))


def strip_json(value):
    if isinstance(value, dict):
        return {k: strip_json(v) for k, v in value.items() if not timing_key(k)}
    if isinstance(value, list):
        return [strip_json(v) for v in value]
    return value


def dump(value):
    return json.dumps(value, sort_keys=True, indent=1) + "\n"


def strip_csv(text):
    rows = list(csv.reader(io.StringIO(text)))
    if not rows:
        return text
    keep = [i for i, h in enumerate(rows[0]) if not timing_key(h)]
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    for row in rows:
        writer.writerow([row[i] for i in keep if i < len(row)])
    return out.getvalue()


NUMBER = r"-?[0-9][0-9.eE+-]*"


def strip_text(text):
    # Markdown tables: drop the columns whose header names wall time.
    lines = text.split("\n")
    drop = None
    for i, line in enumerate(lines):
        if line.startswith("|"):
            cells = line.strip().strip("|").split("|")
            if drop is None:
                drop = {k for k, c in enumerate(cells)
                        if re.search(r"wall|seconds|time to|[( ]s\)", c.lower())}
            lines[i] = "|".join([""] + [c for k, c in enumerate(cells) if k not in drop] + [""])
        else:
            drop = None
    text = "\n".join(lines)
    text = re.sub(r"in " + NUMBER + r" s\b", "in X s", text)
    text = re.sub(NUMBER + r" s (of [a-z ]*)?wall time", r"X s \1wall time", text)
    return text


def strip_html(text):
    # Values bound to a timing JSON key: the attribute and the shown text.
    text = re.sub(r'(data-json="[^"#]*#[^"]*(?:seconds|wall|elapsed)[^"]*" data-value=")[^"]*(">)[^<]*',
                  lambda m: m.group(1) + "X" + m.group(2) + "X", text)
    # The plot of misfit against wall time.
    text = re.sub(r"<svg(?:(?!</svg>).)*?<title>Misfit against wall time</title>.*?</svg>",
                  "<svg>misfit against wall time</svg>", text, flags=re.S)
    return strip_text(text)


def normalise(path):
    with open(path, encoding="utf-8") as f:
        text = f.read()
    if path.endswith(".jsonl"):
        return "".join(dump(strip_json(json.loads(l))) for l in text.splitlines() if l.strip())
    if path.endswith(".json"):
        return dump(strip_json(json.loads(text)))
    if path.endswith(".csv"):
        return strip_csv(text)
    if path.endswith(".html"):
        return strip_html(text)
    return strip_text(text)


def main():
    runs, target = sys.argv[1], sys.argv[2]
    for root, _, files in sorted(os.walk(runs)):
        for name in sorted(files):
            path = os.path.join(root, name)
            rel = os.path.relpath(path, runs)
            text = normalise(path)
            dest = os.path.join(target, rel)
            os.makedirs(os.path.dirname(dest), exist_ok=True)
            with open(dest, "w", encoding="utf-8") as f:
                f.write(text)
            print(hashlib.sha256(text.encode("utf-8")).hexdigest() + "  " + rel)


if __name__ == "__main__":
    main()
