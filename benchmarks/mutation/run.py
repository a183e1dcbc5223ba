#!/usr/bin/python3
"""Mutation benchmark: does the test suite catch plausible bugs?

Each entry of mutations.json is one plausible bug (a sign, a factor, an index, a weight) in one
source file. The script copies the repository's tracked files to a work folder, builds them once,
runs the whole suite to know how each test behaves unmutated, and then, for each bug in turn:
applies it to the copy, rebuilds incrementally, runs the suite against it, and restores the file.
A test can meet a bug in three ways:

  check     the test fails on its own: a check's bound is crossed, softface stops with an error,
            the program crashes or hangs (ctest would report the test failed whatever the
            expected output says);
  snapshot  the test runs to its end but prints numbers other than tests/NAME.output holds
            (numdiff); such a test would be re-blessed by whoever changed the code on purpose;
  -         the test passes unchanged.

A bug is "caught by a check" when some test meets it by a check, "caught by a snapshot only" when
tests meet it only by snapshots, else "not caught". The tests run two at a time, those whose
source names the mutated file's subject first; once a test has failed by a check the bug's run
stops (the remaining tests cannot change its class). `clang_format` is left out: it checks the
layout of the code, which a mutation may change.

usage: /usr/bin/python3 benchmarks/mutation/run.py [--work DIR] [--jobs N] [--only ID ...]
                                                   [--results DIR] [--check]
--check only checks that each bug's text occurs once in its file (the test mutation_texts).
Writes DIR/mutation.md, .csv and .png (default doc/results) and the run's log to WORK/log.txt.
Each bug's outcome is kept in WORK/outcomes/ID.json with a hash of the bug and of every source
file: run again on the same sources (after an interruption, say), a bug already measured is not
measured again.
Needs cmake, the build's dependencies (./test.sh installs them), numdiff and python3-matplotlib.
A fresh work folder takes one full build (about 20 minutes on 2 cores) before the first bug.
"""
import argparse, csv, hashlib, json, os, platform, re, shutil, signal, subprocess, sys, time
from concurrent.futures import ThreadPoolExecutor, wait, FIRST_COMPLETED

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
LEFT_OUT = {"clang_format": "checks the code's layout, which a mutation may change"}


LOG = None          # WORK/log.txt once the work folder exists


def log(message):
    line = time.strftime("%H:%M:%S ") + message
    print(line, flush=True)
    if LOG is not None:
        LOG.write(line + "\n")
        LOG.flush()


def run(command, **kwargs):
    return subprocess.run(command, check=True, **kwargs)


def copy_sources(work):
    """The tracked files of the working tree into WORK/src; a file whose content is already there
    is left alone, so that the build stays incremental."""
    source = os.path.join(work, "src")
    files = subprocess.run(["git", "ls-files", "-z"], cwd=REPO, check=True,
                           capture_output=True).stdout.decode().split("\0")
    copied = 0
    for name in filter(None, files):
        origin, target = os.path.join(REPO, name), os.path.join(source, name)
        if not os.path.isfile(origin):
            continue
        with open(origin, "rb") as f:
            content = f.read()
        if os.path.isfile(target):
            with open(target, "rb") as f:
                if f.read() == content:
                    continue
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copy2(origin, target)
        copied += 1
    # The browser test's packages (./test.sh installs them; untracked): shared, not copied.
    modules = os.path.join(REPO, "web", "node_modules")
    link = os.path.join(source, "web", "node_modules")
    if os.path.isdir(modules) and not os.path.exists(link):
        os.symlink(modules, link)
    return source, copied


def build(source, jobs):
    build_dir = os.path.join(source, "build")
    env = dict(os.environ, CCACHE_BASEDIR=source)
    if not os.path.isfile(os.path.join(build_dir, "CMakeCache.txt")):
        run(["cmake", "-S", source, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release"],
            stdout=subprocess.DEVNULL, env=env)
    result = subprocess.run(["cmake", "--build", build_dir, "-j", str(jobs)], env=env,
                            capture_output=True, text=True)
    return build_dir, result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]


def suite(build_dir):
    """The ctest tests as (name, command, working directory, environment, timeout)."""
    listing = json.loads(subprocess.run(["ctest", "--show-only=json-v1"], cwd=build_dir,
                                        check=True, capture_output=True, text=True).stdout)
    tests = []
    for test in listing["tests"]:
        if test["name"] in LEFT_OUT:
            continue
        properties = {p["name"]: p["value"] for p in test.get("properties", [])}
        env = dict(os.environ)
        for assignment in properties.get("ENVIRONMENT", []):
            key, _, value = assignment.partition("=")
            env[key] = value
        tests.append(dict(name=test["name"], command=test["command"],
                          cwd=properties.get("WORKING_DIRECTORY", build_dir), env=env,
                          timeout=float(properties.get("TIMEOUT", 1500))))
    return tests


def run_test(test, timeout):
    """'pass', 'check' or 'snapshot' (and a line saying why) for one test."""
    start = time.time()
    try:
        process = subprocess.Popen(test["command"], cwd=test["cwd"], env=test["env"],
                                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                   start_new_session=True)
        output, _ = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.communicate()
        return "check", f"ran past {timeout:.0f} s", time.time() - start
    seconds = time.time() - start
    if process.returncode == 0:
        return "pass", "", seconds
    # run_test.cmake says which: the program exited non-zero, or its output differs.
    if "output differs from" in output and "bad_input" not in test["name"]:
        return "snapshot", "", seconds
    reason = re.search(r"test \S+ failed[^:]*: (.*)", output)
    if reason:
        why = reason.group(1).strip()
    elif "bad_input" in test["name"]:
        why = "its message or exit code changed"
    else:
        why = output.strip().splitlines()[-1] if output.strip() else "failed"
    return "check", why[:160], seconds


def relevance(test, mutation, source):
    """Tests whose source or scene names the mutated file's subject run first."""
    stem = os.path.splitext(os.path.basename(mutation["file"]))[0]
    words = {stem, stem.replace("_", " "), "".join(w.title() for w in stem.split("_"))}
    name = test["name"].split(".mpirun")[0].replace("bad_input/", "")
    text = ""
    for candidate in (f"tests/{name}.cc", f"tests/{name}.prm", f"tests/bad_input/{name}.prm"):
        path = os.path.join(source, candidate)
        if os.path.isfile(path):
            with open(path, errors="replace") as f:
                text += f.read().lower()
    return any(w.lower() in text or w.lower() in name.lower() for w in words)


def run_suite(tests, order, jobs, timeouts, stop_on_check):
    """Runs tests in the given order, jobs at a time; returns {name: (class, why, seconds)}."""
    results = {}
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        pending, queue, stopped = set(), list(order), False
        while queue or pending:
            while queue and len(pending) < jobs and not stopped:
                test = queue.pop(0)
                future = pool.submit(run_test, test, timeouts.get(test["name"], test["timeout"]))
                future.test = test
                pending.add(future)
            if not pending:
                break
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            for future in done:
                results[future.test["name"]] = future.result()
                if stop_on_check and future.result()[0] == "check":
                    stopped, queue = True, []
    return results


def apply(source, mutation):
    path = os.path.join(source, mutation["file"])
    with open(path) as f:
        original = f.read()
    if original.count(mutation["find"]) != 1:
        raise SystemExit(f"mutation {mutation['id']}: its text occurs "
                         f"{original.count(mutation['find'])} times in {mutation['file']}, "
                         "not once")
    with open(path, "w") as f:
        f.write(original.replace(mutation["find"], mutation["replace"]))
    return path, original


def sources_hash(source):
    """A hash of every tracked file's content in the copy (the suite and the code it tests)."""
    digest = hashlib.sha1()
    files = subprocess.run(["git", "ls-files", "-z"], cwd=REPO, check=True,
                           capture_output=True).stdout.decode().split("\0")
    for name in sorted(filter(None, files)):
        path = os.path.join(source, name)
        if name.startswith("benchmarks/mutation/") or not os.path.isfile(path):
            continue
        digest.update(name.encode())
        with open(path, "rb") as f:
            digest.update(hashlib.sha1(f.read()).digest())
    return digest.hexdigest()


def classify(results):
    if any(r[0] == "check" for r in results.values()):
        return "check"
    if any(r[0] == "snapshot" for r in results.values()):
        return "snapshot"
    return "not caught"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--work", default="/tmp/softface-mutation")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--only", nargs="*", help="run these mutation ids only")
    parser.add_argument("--results", default=os.path.join(REPO, "doc", "results"))
    parser.add_argument("--check", action="store_true",
                        help="only check that each bug's text occurs once in its file of this "
                             "repository (a bug the code has moved away from tests nothing)")
    args = parser.parse_args()

    if args.check:
        with open(os.path.join(REPO, "benchmarks", "mutation", "mutations.json")) as f:
            mutations = json.load(f)
        stale = 0
        for mutation in mutations:
            with open(os.path.join(REPO, mutation["file"])) as f:
                count = f.read().count(mutation["find"])
            if count != 1:
                print(f"{mutation['id']}: its text occurs {count} times in {mutation['file']}")
                stale += 1
        print(f"{len(mutations)} bugs, {stale} whose text does not occur once")
        sys.exit(min(stale, 1))

    os.makedirs(args.work, exist_ok=True)
    global LOG
    LOG = open(os.path.join(args.work, "log.txt"), "a")
    with open(os.path.join(REPO, "benchmarks", "mutation", "mutations.json")) as f:
        mutations = json.load(f)
    if args.only:
        mutations = [m for m in mutations if m["id"] in args.only]
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=REPO, check=True,
                            capture_output=True, text=True).stdout.strip()

    source, copied = copy_sources(args.work)
    log(f"{copied} files copied to {source}; building")
    started = time.time()
    build_dir, ok, output = build(source, args.jobs)
    if not ok:
        raise SystemExit("the unmutated copy does not build:\n" + output)
    log(f"built in {time.time() - started:.0f} s; the unmutated suite")
    tests = suite(build_dir)
    baseline = run_suite(tests, tests, args.jobs, {}, stop_on_check=False)
    failing = sorted(n for n, r in baseline.items() if r[0] != "pass")
    if failing:
        log("left out, failing unmutated: " + ", ".join(failing))
    tests = [t for t in tests if t["name"] not in failing]
    seconds = {n: r[2] for n, r in baseline.items()}
    timeouts = {t["name"]: min(t["timeout"], 3 * seconds[t["name"]] + 60) for t in tests}
    log(f"{len(tests)} tests, {sum(seconds[t['name']] for t in tests):.0f} s of test time")

    outcomes = []
    kept = os.path.join(args.work, "outcomes")
    os.makedirs(kept, exist_ok=True)
    tree = sources_hash(source)
    for number, mutation in enumerate(mutations, 1):
        key = hashlib.sha1((tree + json.dumps(mutation, sort_keys=True)).encode()).hexdigest()
        record = os.path.join(kept, mutation["id"] + ".json")
        if os.path.isfile(record):
            with open(record) as f:
                earlier = json.load(f)
            if earlier.get("key") == key:
                outcomes.append(earlier)
                log(f"[{number}/{len(mutations)}] {mutation['id']}: {earlier['outcome']} "
                    "(measured before on the same sources)")
                continue
        path, original = apply(source, mutation)
        try:
            started = time.time()
            _, ok, output = build(source, args.jobs)
            build_seconds = time.time() - started
            if not ok:
                log(f"[{number}/{len(mutations)}] {mutation['id']}: does not compile\n{output}")
                outcome = dict(mutation, outcome="does not compile", tests_run=0, caught_by="",
                               why="", snapshot_tests="", key=key)
                outcomes.append(outcome)
                continue
            first = [t for t in tests if relevance(t, mutation, source)]
            rest = [t for t in tests if t not in first]
            order = sorted(first, key=lambda t: seconds[t["name"]]) + \
                sorted(rest, key=lambda t: seconds[t["name"]])
            started = time.time()
            results = run_suite(tests, order, args.jobs, timeouts, stop_on_check=True)
            outcome = classify(results)
            checks = [n for n, r in results.items() if r[0] == "check"]
            snapshots = sorted(n for n, r in results.items() if r[0] == "snapshot")
            outcomes.append(dict(mutation, outcome=outcome, tests_run=len(results),
                                 caught_by=checks[0] if checks else "",
                                 why=results[checks[0]][1] if checks else "",
                                 snapshot_tests=" ".join(snapshots), key=key))
            with open(record, "w") as f:
                json.dump(outcomes[-1], f)
            log(f"[{number}/{len(mutations)}] {mutation['id']}: {outcome} "
                f"({checks[0] if checks else ', '.join(snapshots) or 'no test'}; "
                f"{len(results)} tests in {time.time() - started:.0f} s, "
                f"build {build_seconds:.0f} s)")
        finally:
            with open(path, "w") as f:
                f.write(original)
    build(source, args.jobs)          # leave the copy built unmutated

    report(outcomes, len(tests), failing, commit, args)


def report(outcomes, n_tests, failing, commit, args):
    os.makedirs(args.results, exist_ok=True)
    fields = ["id", "subsystem", "file", "bug", "outcome", "caught_by", "why", "snapshot_tests",
              "tests_run"]
    with open(os.path.join(args.results, "mutation.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(outcomes)

    compiled = [o for o in outcomes if o["outcome"] != "does not compile"]
    subsystems = sorted({o["subsystem"] for o in compiled})
    classes = ["check", "snapshot", "not caught"]
    count = {s: {c: sum(1 for o in compiled if o["subsystem"] == s and o["outcome"] == c)
                 for c in classes} for s in subsystems}
    total = {c: sum(count[s][c] for s in subsystems) for c in classes}
    n = len(compiled)
    percent = lambda k: 100.0 * k / n if n else 0.0
    machine = f"{platform.node() or 'this machine'}, {os.cpu_count()} cores, {platform.platform()}"
    lines = ["# Mutation benchmark: do the tests catch plausible bugs?", "",
             "Whether the test suite catches plausible bugs planted one at a time in each "
             "subsystem, and how: by a check of its own or only by a changed snapshot.", "",
             "Reproduce: `/usr/bin/python3 benchmarks/mutation/run.py` (about an hour on 2 "
             "cores: a full build, the suite once, then about 40 s per bug).", "",
             f"Measured at commit {commit} on {machine}.", "",
             f"{len(outcomes)} bugs listed in `benchmarks/mutation/mutations.json`, each applied "
             f"alone to a copy of the source, rebuilt and run against {n_tests} tests "
             "(`clang_format` left out: it checks the code's layout).",
             "*check*: at least one test fails on its own (a check's bound, an error, a crash or "
             "a hang); *snapshot only*: tests run to their end and only their printed numbers "
             "differ from `tests/NAME.output`; *not caught*: every test passes.", ""]
    if failing:
        lines += ["Left out because they fail without any bug: " + ", ".join(failing) + ".", ""]
    lines += ["| subsystem | bugs | caught by a check | by a snapshot only | not caught |",
              "|---|---:|---:|---:|---:|"]
    for s in subsystems:
        k = count[s]
        lines.append(f"| {s} | {sum(k.values())} | {k['check']} | {k['snapshot']} | "
                     f"{k['not caught']} |")
    lines.append(f"| **all** | **{n}** | **{total['check']} ({percent(total['check']):.0f} %)** "
                 f"| **{total['snapshot']} ({percent(total['snapshot']):.0f} %)** | "
                 f"**{total['not caught']} ({percent(total['not caught']):.0f} %)** |")
    caught = total["check"] + total["snapshot"]
    lines += ["", "![planted bugs per subsystem and how they were caught](mutation.png)", "",
              "## What the numbers show", "",
              f"- Caught: {caught} of {n} ({percent(caught):.0f} %, target at least 90 %); "
              f"through a check: {total['check']} ({percent(total['check']):.0f} %, target at "
              "least 75 %).",
              f"- Not caught: {total['not caught']}; caught by a snapshot only: "
              f"{total['snapshot']}.", "",
              "## Limits", "",
              "- The bugs are planted by hand, one at a time: the figures say how well the tests "
              "guard against bugs like these, not against every bug.", ""]
    uncompiled = [o["id"] for o in outcomes if o["outcome"] == "does not compile"]
    if uncompiled:
        lines += ["Did not compile (left out of the counts): " + ", ".join(uncompiled) + ".", ""]
    lines += ["## Each bug", "",
              "| bug | subsystem | file | outcome | first test that failed (why) |",
              "|---|---|---|---|---|"]
    for o in outcomes:
        if o["outcome"] == "check":
            seen = f"`{o['caught_by']}` ({o['why']})".replace("|", "/")
        elif o["outcome"] == "snapshot":
            seen = "snapshots of " + ", ".join(f"`{t}`" for t in o["snapshot_tests"].split())
        else:
            seen = ""
        lines.append(f"| {o['bug']} | {o['subsystem']} | `{o['file']}` | {o['outcome']} | "
                     f"{seen} |")
    with open(os.path.join(args.results, "mutation.md"), "w") as f:
        f.write("\n".join(lines) + "\n")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        log("python3-matplotlib is missing: mutation.png not written")
        return
    fig, ax = plt.subplots(figsize=(8, 0.45 * len(subsystems) + 1.5))
    left = [0] * len(subsystems)
    for c, colour in zip(classes, ["#2a9d8f", "#e9c46a", "#e76f51"]):
        values = [count[s][c] for s in subsystems]
        ax.barh(subsystems, values, left=left, color=colour,
                label={"check": "caught by a check", "snapshot": "by a snapshot only",
                       "not caught": "not caught"}[c])
        left = [a + b for a, b in zip(left, values)]
    ax.invert_yaxis()
    ax.set_xlabel("planted bugs")
    ax.set_title(f"Mutation benchmark: {caught} of {n} caught, {total['check']} by a check")
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(os.path.join(args.results, "mutation.png"), dpi=120)


if __name__ == "__main__":
    main()
