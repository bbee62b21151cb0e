"""Habitat's ``utils.manager_utils``: write a manager's comma-separated report to a CSV file.

Template managers and the metadata mediator describe their contents as text, one line per
entry with comma-separated fields (``MetadataMediator.dataset_report()``).
:func:`save_csv_report` writes such a text as a CSV file with every field quoted, so a
spreadsheet reads handles that contain spaces or commas correctly.
"""

from __future__ import annotations

import csv
from pathlib import Path

__all__ = ["save_csv_report"]


def save_csv_report(file_name: str | Path, report_string: str) -> None:
    """Write ``report_string`` (lines of comma-separated fields) to ``file_name`` as CSV.

    Each line becomes one row, split on commas, every field quoted (``csv.QUOTE_ALL``); an
    empty report writes an empty file. An existing file is overwritten.
    """
    if not isinstance(report_string, str):
        raise TypeError(f"report_string must be a str, got {type(report_string).__name__}")
    with open(file_name, "w", newline="", encoding="utf-8") as handle:
        writer = csv.writer(handle, quoting=csv.QUOTE_ALL)
        for line in report_string.splitlines():
            writer.writerow(line.split(","))
