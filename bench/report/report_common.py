"""What the report's plotting scripts share: reading the CSVs and their .meta files, formatting
numbers, and the footer every figure carries (machine, compiler, flags, date)."""
import csv
import math
import os
import textwrap


def fnum(s):
    """A CSV field as a float (NaN when empty or not a number)."""
    try:
        return float(s)
    except (TypeError, ValueError):
        return math.nan


def read_rows(path):
    """The rows of a CSV as dicts; [] when the file does not exist."""
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read_meta(path):
    """The key: value lines a driver wrote beside its CSV (hard_cases.cpp's write_meta)."""
    meta = {}
    if os.path.exists(path):
        with open(path) as f:
            for line in f:
                key, sep, value = line.partition(": ")
                if sep:
                    meta[key.strip()] = value.strip()
    return meta


def provenance(meta):
    """One line: machine, compiler, flags, date."""
    return "{} ({} cores), {}, {}, flags '{}', {}, {} run".format(
        meta.get("cpu", "?"), meta.get("cores", "?"), meta.get("kernel", "?"),
        meta.get("compiler", "?"), meta.get("flags", "?").strip(), meta.get("date", "?"),
        meta.get("mode", "?"))


def add_footer(fig, meta, extra=""):
    """Writes the provenance under a figure, so that a PNG seen alone says where it comes from."""
    text = provenance(meta) + (" | " + extra if extra else "")
    fig.text(0.01, 0.005, textwrap.fill(text, width=200), fontsize=6.5, color="dimgray",
             va="bottom")


def fmt(x, digits=2):
    """A number for a table: 3 significant digits, scientific when small or large."""
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    if math.isinf(x):
        return "blows up"
    if x == 0:
        return "0"
    return f"{x:.{digits}e}" if (abs(x) < 1e-2 or abs(x) >= 1e5) else f"{x:.{digits + 1}g}"


def median(values):
    v = sorted(x for x in values if not math.isnan(x))
    if not v:
        return math.nan
    n = len(v)
    return v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2])


def md_table(header, rows):
    """A Markdown table from a header list and rows of strings."""
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)
