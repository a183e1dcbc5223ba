"""softface's summary.csv, read by column name: every benchmark report takes its
figures from there, never from what softface prints."""
import csv
import os


def read(path):
    """All rows of a summary.csv as dicts (empty list if the file is missing)."""
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def row(path, model):
    """The row of one model, or None."""
    return next((r for r in read(path) if r["model"] == model), None)


def pairs(text):
    """'name=value;name=value' (the phases and details columns) as a dict."""
    out = {}
    for item in text.split(";") if text else []:
        name, _, value = item.partition("=")
        out[name] = value
    return out


def phases_text(text):
    """The phases column as 'name 0.123 s, ...'."""
    return ", ".join(f"{n} {float(v):.3f} s" for n, v in pairs(text).items())


def details_text(text):
    """The details column as 'name value, ...' (numbers to four digits)."""
    items = []
    for name, value in pairs(text).items():
        number, _, unit = value.partition(" ")
        try:
            x = float(number)
            number = str(int(x)) if x == int(x) and abs(x) < 1e15 else f"{x:.4g}"
        except ValueError:
            pass
        items.append(f"{name} {number}{' ' + unit if unit else ''}")
    return ", ".join(items)


def write_rows(path, rows, fieldnames=None):
    """ROWS (dicts) as a CSV file; the columns are FIELDNAMES, or the first
    row's keys."""
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fieldnames or list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)


def measured_at(cpu):
    """The reproduction line's second half: the commit the code was at and the
    machine, e.g. "Measured at commit <hash> on AMD EPYC, 2 cores."."""
    import subprocess
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip() or "unknown"
    return f"Measured at commit {commit} on {cpu}, {os.cpu_count()} cores."
