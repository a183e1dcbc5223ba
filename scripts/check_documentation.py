#!/usr/bin/env python3
"""Checks that softface's manual holds together.

- Every relative link and image in README.md and doc/**/*.md resolves to a
  file of the repository, and a link to a heading (page.md#heading) to a
  heading of that page (GitHub's anchors: lower case, punctuation dropped,
  spaces as hyphens).
- Every PNG under doc/ is shown or linked on some page.
- The README's quick start is two commands, and the one that tests is the
  command .ci/run runs.
- README.md is at most 150 lines.
- README.md, doc/, source/, include/ and app/ name no issue, carry no commit
  hash (a results page may name its commit on one line, the one that says
  how it was measured) and no first person.

Each failure is listed with the file and line; the exit code is the number
of failures (0: the manual holds). Run from anywhere:

    scripts/check_documentation.py [repository]
"""
import os
import re
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                       os.path.join(os.path.dirname(__file__), ".."))
README_MAX_LINES = 150

LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
ISSUE = re.compile(r"\b[Ii]ssues?\s+#?\d+|\(#\d+\)|\bissue #\d+")
# A commit hash as git abbreviates it: 7 to 9 hexadecimal digits, letters and
# digits both (longer ones, such as the md5 sums a results page lists, are data).
HASH = re.compile(r"(?<![0-9A-Za-z_./-])(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])"
                  r"[0-9a-f]{7,9}(?![0-9A-Za-z_])")
FIRST_PERSON = re.compile(
    r"\bI(?:'m|'ve|'d|'ll)\b|\b[Mm]y\b|"
    r"\bI (?:am|was|have|had|did|do|ran|run|measured|tried|think|used|"
    r"found|made|checked|see|saw|wrote|printed|kept|left|chose|could|can|"
    r"will|would|added|changed|removed|fixed|looked|believe|suspect)\b")


def relative(path):
    return os.path.relpath(path, ROOT)


def pages():
    """README.md and every Markdown page under doc/."""
    yield os.path.join(ROOT, "README.md")
    for folder, _, files in os.walk(os.path.join(ROOT, "doc")):
        for name in sorted(files):
            if name.endswith(".md"):
                yield os.path.join(folder, name)


def anchor(heading):
    text = re.sub(r"[`*_]", "", heading.strip().lower())
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors_of(page):
    found, in_code = set(), False
    with open(page, encoding="utf-8", errors="replace") as f:
        for line in f:
            if line.startswith("```"):
                in_code = not in_code
            elif not in_code and re.match(r"#{1,6} ", line):
                found.add(anchor(line.lstrip("#")))
    return found


def check_links(failures, shown):
    for page in pages():
        in_code = False
        with open(page, encoding="utf-8", errors="replace") as f:
            for number, line in enumerate(f, 1):
                if line.startswith("```"):
                    in_code = not in_code
                if in_code:
                    continue
                for target in LINK.findall(line):
                    if re.match(r"[a-z]+:", target):
                        continue
                    path, _, heading = target.partition("#")
                    file = (os.path.normpath(
                        os.path.join(os.path.dirname(page), path))
                            if path else page)
                    where = "%s:%d" % (relative(page), number)
                    if not os.path.exists(file):
                        failures.append("%s: link to '%s': no such file" %
                                        (where, target))
                        continue
                    shown.add(file)
                    if heading and file.endswith(".md") and \
                       heading not in anchors_of(file):
                        failures.append("%s: link to '%s': no such heading"
                                        % (where, target))


def check_pictures(failures, shown):
    for folder, _, files in os.walk(os.path.join(ROOT, "doc")):
        for name in sorted(files):
            file = os.path.join(folder, name)
            if name.endswith(".png") and file not in shown:
                failures.append("%s: shown on no page" % relative(file))


def check_quick_start(failures):
    with open(os.path.join(ROOT, "README.md"), encoding="utf-8",
              errors="replace") as f:
        lines = f.read().split("\n")
    if len(lines) - 1 > README_MAX_LINES:
        failures.append("README.md: %d lines, more than %d" %
                        (len(lines) - 1, README_MAX_LINES))
    try:
        start = lines.index("## Quick start")
    except ValueError:
        failures.append("README.md: no section '## Quick start'")
        return
    commands = []
    for line in lines[start + 1:]:
        if line.startswith("## "):
            break
        if line.startswith("    ./") or line.startswith("./"):
            commands.append(line.split("#")[0].strip())
    with open(os.path.join(ROOT, ".ci", "run"), encoding="utf-8",
              errors="replace") as f:
        ci = [l.split()[-1] for l in f if l.startswith("exec ")]
    if commands[:1] != ["./run.sh"] or len(commands) != 2:
        failures.append("README.md: the quick start is not './run.sh' and "
                        "one test command (found %s)" % commands)
    elif commands[1:] != ci:
        failures.append("README.md: the quick start tests with %s, .ci/run "
                        "with %s" % (commands[1:], ci))


def text_files():
    yield os.path.join(ROOT, "README.md")
    for top in ("doc", "source", "include", "app"):
        for folder, _, files in os.walk(os.path.join(ROOT, top)):
            for name in sorted(files):
                if name.endswith((".md", ".cc", ".h", ".py", ".sh", ".prm",
                                  ".txt", ".js", ".html")):
                    yield os.path.join(folder, name)


def check_history(failures):
    for file in text_files():
        results_page = (relative(file).startswith("doc/results/") and
                        file.endswith(".md"))
        with open(file, encoding="utf-8", errors="replace") as f:
            for number, line in enumerate(f, 1):
                where = "%s:%d" % (relative(file), number)
                if "\ufffd" in line and file.endswith(".md"):
                    failures.append("%s: not UTF-8" % where)
                if ISSUE.search(line):
                    failures.append("%s: names an issue: %s" %
                                    (where, line.strip()[:100]))
                if FIRST_PERSON.search(line):
                    failures.append("%s: first person: %s" %
                                    (where, line.strip()[:100]))
                hashes = HASH.findall(line)
                if hashes and not (results_page and
                                   re.search(r"\bcommit\b", line)):
                    failures.append("%s: commit hash %s" %
                                    (where, ", ".join(hashes)))


def main():
    failures, shown = [], set()
    check_links(failures, shown)
    check_pictures(failures, shown)
    check_quick_start(failures)
    check_history(failures)
    for failure in failures:
        print(failure)
    print("%d failures" % len(failures))
    return min(len(failures), 255)


if __name__ == "__main__":
    sys.exit(main())
