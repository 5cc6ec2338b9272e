"""A case's table as run.py writes it (bench/results/fullwave/CASE.csv: one row per observer and the FDTD reference),
read back by the scripts that compare other models with the same reference."""
from __future__ import annotations

import cmath
import csv
import os
import sys


def rows_by_observer(out_dir: str, name: str, program: str, labels=()) -> dict[str, dict[str, str]]:
    """The rows of case `name`'s table in `out_dir`, by observer label. A missing table, or a missing row for one of
    `labels`, is an error naming the file (and the label) and the command that writes it (exit 2)."""
    path = os.path.join(out_dir, name + ".csv")
    if not os.path.isfile(path):
        print(f"{program}: error: {path}: not found (run.py --case {name} first)", file=sys.stderr)
        sys.exit(2)
    with open(path, newline="") as f:
        rows = {r["observer"]: r for r in csv.DictReader(f)}
    for label in labels:
        if label not in rows:
            print(f"{program}: error: {path}: no row for observer {label} (run.py --case {name} again)", file=sys.stderr)
            sys.exit(2)
    return rows


def ratio(row: dict[str, str], column: str) -> complex:
    """A complex ratio of the table (`fdtd`: E/E_free; a level's name with `-` as `_`: h/h_ideal) from its
    `COLUMN_abs` and `COLUMN_arg_rad` fields."""
    return cmath.rect(float(row[column + "_abs"]), float(row[column + "_arg_rad"]))
