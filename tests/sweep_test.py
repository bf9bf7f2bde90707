#!/usr/bin/python3
"""Tests of `cmc sweep` (solver/app/cmd_sweep.cpp): a sweep's points are `cmc run`'s runs,
an interrupted sweep resumes, finished points are not run again, bad input is refused.

usage: tests/sweep_test.py CMC WORKDIR TEST

TEST is one of
  same_as_run   the Tabor case over mu_T = 1.0, 3.0 and the grids 32² and 64² (fields on):
                every point's folder equals `cmc run` with the same --set bit for bit
                (scripts/compare_runs.py: summary.json and result.h5), and sweep.json and
                sweep.md hold one record / row per point with the numbers of its summary.json
  resume        the same sweep killed inside its second point (between two outer steps of
                the solve, --checkpoint-every 0), then run again: the finished point is
                skipped, the killed one resumes from its checkpoint, and every point equals
                the uninterrupted sweep's bit for bit
  skip          a finished sweep run again runs nothing (every point "converged earlier",
                its summary.json untouched) and exits 0; a point stopped at
                solver.max_outer_steps is reported not converged (exit 3, the other point
                runs), and run again it is kept as it is (exit 3)
  refusals      bad input exits 2 naming the argument before anything is written: an unknown
                key, a malformed value, an empty list or value, a repeated value or key, a
                --set of the swept key, grid.n beside --grids, a folder pattern that gives two
                points one folder, leaves --out, names the table or cmc's own files, a table
                name with a folder, a bad grid size, a single-value option given twice; and a
                point folder holding a run of another case, or a summary.json that is not
                cmc's, stops the sweep before its first point runs, the folder left as it was
  many_values   10,000 values of one key with --dry-run: checked in linear time
  folders       a symbolic link on the way to a point's folder is refused before anything
                runs; a damaged checkpoint's message says how to start the point afresh
  scaled_family scripts/scaled_family.py's runs go through cmc sweep: member s = 32 on 64² and
                128², plain and with the range strategy, and under the hard wall (--store into
                the work folder): every stored run's recorded command, `cmc run` into another
                folder, gives its folder bit for bit; run again, the script runs nothing

Runs use CMC_THREADS=1 (the same bits in every run). Exits 0 on success, 1 with the
reasons on failure.
"""
import json
import os
import re
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
from resume_test import COMPARE, check, failures  # noqa: E402  (the interruption tests' helpers)

TABOR = os.path.join(ROOT, "cases", "challenge", "tabor-sweep.toml")    # quasi-static, one step
FAMILY = os.path.join(ROOT, "cases", "challenge", "scaled-family.toml")  # 7 outer steps at 128²
SWEEP = ["--over", "interaction.tabor=1.0,3.0", "--grids", "32", "64", "--set", "output.fields=true"]
POINTS = [("1.0", 32), ("1.0", 64), ("3.0", 32), ("3.0", 64)]

def cmc(binary, *args, **extra):
    env = {k: v for k, v in os.environ.items() if not k.startswith("CMC_TEST_")}
    env.update(CMC_THREADS="1", **extra)
    return subprocess.run([binary, *args], env=env, capture_output=True, text=True, cwd=ROOT)


def sweep(binary, out, *args, **extra):
    return cmc(binary, "sweep", TABOR, "--out", out, "--quiet", *SWEEP, *args, **extra)


def folder(out, mu, n):
    return os.path.join(out, f"interaction.tabor_{mu}", f"n{n}")


def same(a, b, label):
    p = subprocess.run(["/usr/bin/python3", COMPARE, a, b], capture_output=True, text=True)
    return check(p.returncode == 0, f"{label}: {b} differs from {a}:\n{p.stdout}{p.stderr}")


def summary(path):
    with open(os.path.join(path, "summary.json"), encoding="utf-8") as f:
        return json.load(f)


def finished_sweep(binary, work, name="sweep"):
    out = os.path.join(work, name)
    shutil.rmtree(out, ignore_errors=True)
    p = sweep(binary, out)
    if p.returncode != 0:
        raise SystemExit(f"sweep_test: the sweep failed ({p.returncode}):\n{p.stderr}")
    return out, p


def test_same_as_run(binary, work):
    out, p = finished_sweep(binary, work)
    with open(os.path.join(out, "sweep.json"), encoding="utf-8") as f:
        table = json.load(f)
    check(table["status"] == "converged" and len(table["points"]) == 4, f"sweep.json: {table}")
    with open(os.path.join(out, "sweep.md"), encoding="utf-8") as f:
        rows = [line for line in f if line.startswith("| 1.0 |") or line.startswith("| 3.0 |")]
    check(len(rows) == 4 and p.stdout.count("| converged |") == 4, f"sweep.md / stdout: {rows}\n{p.stdout}")
    for (mu, n), record in zip(POINTS, table["points"]):
        run = os.path.join(work, "runs", f"{mu}-n{n}")
        shutil.rmtree(run, ignore_errors=True)
        r = cmc(binary, "run", TABOR, "--out", run, "--quiet", "--set", "output.fields=true",
                "--set", f"interaction.tabor={mu}", "--set", f"grid.n={n}")
        if not check(r.returncode == 0, f"cmc run mu_T = {mu}, n = {n}: exit {r.returncode}:\n{r.stderr}"):
            continue
        same(run, folder(out, mu, n), f"the sweep's point mu_T = {mu}, n = {n} against cmc run")
        last = summary(run)["steps"][-1]
        want = {"values": {"interaction.tabor": mu}, "grid": [n, n], "status": "converged", "how": "ran",
                "folder": f"interaction.tabor_{mu}/n{n}", "contact_fraction": last["contact_fraction"],
                "repulsive_fraction": last["observables"]["repulsive_fraction"], "mean_gap_m": last["mean_gap"],
                "mean_pressure_Pa": last["mean_pressure"], "iterations": last["iterations"]}
        got = {k: record.get(k) for k in want}
        check(got == want, f"sweep.json's record of mu_T = {mu}, n = {n}: {got}, expected {want}")


def kill_point(binary, work):
    """The trace of an uninterrupted sweep: the second outer step of its second point."""
    out = os.path.join(work, "traced")
    shutil.rmtree(out, ignore_errors=True)
    p = sweep(binary, out, "--checkpoint-every", "0", CMC_TEST_TRACE="1")
    second = p.stderr.split("sweep: point 2/4", 1)[1].split("sweep: point 3/4", 1)[0]
    outer = re.findall(r"^cmc: test point outer:(\d+)$", second, re.M)
    assert len(outer) >= 2, f"the second point makes {len(outer)} outer steps, the test needs 2"
    return out, f"outer:{outer[1]}"


def test_resume(binary, work):
    ref, point = kill_point(binary, work)
    out = os.path.join(work, "killed")
    shutil.rmtree(out, ignore_errors=True)
    p = sweep(binary, out, "--checkpoint-every", "0", CMC_TEST_KILL_AT=point)
    check(p.returncode == -9, f"kill at {point}: expected SIGKILL, got exit {p.returncode}:\n{p.stderr}")
    killed = folder(out, "1.0", 64)
    check(os.path.exists(os.path.join(folder(out, "1.0", 32), "summary.json")), "the first point did not finish")
    check(os.path.exists(os.path.join(killed, ".partial", "checkpoint.h5")) and
          not os.path.exists(os.path.join(killed, "summary.json")), f"{killed}: no checkpoint, or a summary")
    check(not os.path.exists(folder(out, "3.0", 32)), "the third point ran before the sweep was killed")
    p = cmc(binary, "sweep", TABOR, "--out", out, *SWEEP, "--checkpoint-every", "0")  # not --quiet: says "inside"
    check(p.returncode == 0, f"the sweep run again: exit {p.returncode}:\n{p.stderr}")
    check("point 1/4 (interaction.tabor=1.0, n = 32): converged earlier: skipped" in p.stderr and
          "point 2/4 (interaction.tabor=1.0, n = 64): resuming" in p.stderr and
          "resuming challenge-tabor-sweep: 0 of 1 steps finished, step 0 inside" in p.stderr,
          f"the sweep run again did not skip the first point and resume the second inside its step:\n{p.stderr}")
    for mu, n in POINTS:
        same(folder(ref, mu, n), folder(out, mu, n), f"mu_T = {mu}, n = {n} after the interruption")
    with open(os.path.join(out, "sweep.json"), encoding="utf-8") as f:
        how = [r["how"] for r in json.load(f)["points"]]
    check(how == ["done earlier", "resumed", "ran", "ran"], f"sweep.json's how: {how}")


def test_skip(binary, work):
    out, _ = finished_sweep(binary, work)
    before = {f: open(os.path.join(f, "summary.json"), "rb").read() for f in (folder(out, *pt) for pt in POINTS)}
    p = sweep(binary, out)
    check(p.returncode == 0 and p.stderr.count("converged earlier: skipped") == 4 and "running" not in p.stderr,
          f"a finished sweep run again: exit {p.returncode}:\n{p.stderr}")
    for f, text in before.items():
        check(open(os.path.join(f, "summary.json"), "rb").read() == text, f"{f}/summary.json was rewritten")
    # A point stopped at its outer-step limit: reported, not fatal; run again, kept as it is.
    out = os.path.join(work, "limit")
    shutil.rmtree(out, ignore_errors=True)
    args = ["sweep", FAMILY, "--out", out, "--quiet", "--set", "grid.n=128", "--over", "solver.max_outer_steps=4,1000"]
    p = cmc(binary, *args)
    stopped = os.path.join(out, "solver.max_outer_steps_4")
    check(p.returncode == 3 and summary(stopped)["status"] == "not_converged" and
          summary(os.path.join(out, "solver.max_outer_steps_1000"))["status"] == "converged",
          f"a sweep with a point stopped at its limit: exit {p.returncode}:\n{p.stderr}")
    text = open(os.path.join(stopped, "summary.json"), "rb").read()
    p = cmc(binary, *args)
    check(p.returncode == 3 and open(os.path.join(stopped, "summary.json"), "rb").read() == text,
          f"the stopped point run again: exit {p.returncode} (expected 3, the folder as it was):\n{p.stderr}")
    with open(os.path.join(out, "sweep.json"), encoding="utf-8") as f:
        table = json.load(f)
    check(table["status"] == "not_converged" and [r["how"] for r in table["points"]] == ["kept", "done earlier"],
          f"sweep.json of the sweep run again: {table['status']}, {[r['how'] for r in table['points']]}")


def test_scaled_family(binary, work):
    results, store = os.path.join(work, "results"), os.path.join(work, "store")
    shutil.rmtree(results, ignore_errors=True)
    args = ["/usr/bin/python3", os.path.join(ROOT, "scripts", "scaled_family.py"), "--s", "32", "--coarse", "--grids",
            "64", "128", "--no-resolved", "--strategies", "range", "--results", results, "--store", store,
            "--cmc", binary]
    env = {k: v for k, v in os.environ.items() if not k.startswith("CMC_TEST_")}
    env["CMC_THREADS"] = "1"
    p = subprocess.run(args, env=env, capture_output=True, text=True, cwd=ROOT)
    if not check(p.returncode == 0 and p.stderr.count("cmc sweep ") == 3,
                 f"scaled_family.py: exit {p.returncode}, expected three cmc sweeps:\n{p.stderr}"):
        return
    with open(os.path.join(store, "scaled_family.json"), encoding="utf-8") as f:
        runs = json.load(f)["members"][0]["runs"]
    check(len(runs) == 6, f"the store holds {len(runs)} runs, expected 6")
    for r in runs:
        command = r["command"].split()
        out = command.index("--out") + 1
        again = os.path.join(work, "again", os.path.basename(command[out]))
        shutil.rmtree(again, ignore_errors=True)
        command[out] = again
        q = cmc(binary, *command[1:], "--quiet")
        if check(q.returncode == 0, f"{r['role']}: its command exited {q.returncode}:\n{q.stderr}"):
            same(r["output"], again, f"{r['role']}: the script's folder against its recorded command")
    p = subprocess.run(args, env=env, capture_output=True, text=True, cwd=ROOT)
    check(p.returncode == 0 and "cmc sweep " not in p.stderr and p.stderr.count(": done (") == 6,
          f"scaled_family.py run again: exit {p.returncode}, expected no sweep and six runs done:\n{p.stderr}")


REFUSALS = [  # (arguments, what the message must name)
    (["--over", "interaction.tabr=1,2"], "[interaction] tabr: unknown key"),
    (["--over", "interaction.tabor=abc"], "the point interaction.tabor=abc"),
    (["--over", "interaction.tabor="], "--over interaction.tabor=: an empty list"),
    (["--over", "interaction.tabor=1,,2"], "--over interaction.tabor=1,,2: value 2 is empty"),
    (["--over", "interaction.tabor=1,1"], "the value 1 comes twice"),
    (["--over", "interaction.tabor=1,1.0"], "the value 1.0 (the same as 1) comes twice"),
    (["--over", "loading.values=[1e4],[10000.0]"], "the value [10000.0] (the same as [1e4]) comes twice"),
    (["--over", "interaction.tabor=1", "--over", "interaction.tabor=2"], "--over interaction.tabor is given twice"),
    (["--over", "tabor=1"], "--over tabor=1: expected section.key=V1,V2"),
    (["--over", "interaction.tabor=[1"], "an unclosed bracket"),
    (["--over", "interaction.tabor=1", "--set", "interaction.tabor=2"], "--set interaction.tabor=2 fixes the swept key"),
    (["--grids", "32", "64", "--set", "grid.n=64"], "--set grid.n=64 overrides --grids 32 64"),
    (["--over", "grid.n=32,64", "--grids", "32", "64"], "--over grid.n=... and --grids both set the grid"),
    (["--over", "interaction.tabor=1,2", "--folder", "x"], "share the folder x"),
    (["--over", "interaction.tabor=1", "--folder", "../x"], "expected a relative path below --out"),
    (["--over", "interaction.tabor=1", "--folder", "{foo}"], "{foo} is neither a swept key"),
    (["--over", "interaction.tabor=1", "--table", "a/b"], "--table 'a/b': expected a file name"),
    (["--grids", "32", "abc"], "--grids: 'abc' is neither a whole number"),
    ([], "cmc sweep needs --over"),
    (["--over", "interaction.tabor=1", "--folder", ".partial"], "'.partial' is the name of cmc's own files"),
    (["--over", "interaction.tabor=1", "--folder", "x/.cmc.lock"], "'.cmc.lock' is the name of cmc's own files"),
    (["--over", "interaction.tabor=1", "--folder", "sweep.json/x"], "where the sweep writes its table (--table sweep)"),
    (["--over", "interaction.tabor=1", "--folder", "t.md", "--table", "t"], "where the sweep writes its table"),
    (["--over", "interaction.tabor=1", "--folder", "a", "--folder", "b"], "--folder is given twice"),
    (["--over", "interaction.tabor=1", "--checkpoint-every", "5", "--checkpoint-every", "6"],
     "--checkpoint-every is given twice"),
]


def test_refusals(binary, work):
    for args, message in REFUSALS:
        out = os.path.join(work, "bad")
        shutil.rmtree(out, ignore_errors=True)
        p = cmc(binary, "sweep", TABOR, "--out", out, "--quiet", *args)
        check(p.returncode == 2 and message in p.stderr and not os.path.exists(out),
              f"cmc sweep {' '.join(args)}: exit {p.returncode} (expected 2, naming '{message}', nothing written):\n"
              f"{p.stderr}")
    # A folder of another case (mu_T = 3.0's run where mu_T = 1.0's belongs), and a foreign
    # summary.json: refused before the first point runs, and left as they were.
    out, _ = finished_sweep(binary, work)
    wrong = folder(out, "1.0", 64)
    shutil.rmtree(wrong)
    shutil.copytree(folder(out, "3.0", 64), wrong)
    shutil.rmtree(folder(out, "1.0", 32))
    p = sweep(binary, out)
    check(p.returncode == 2 and "holds a run of another case (key interaction.tabor" in p.stderr and
          not os.path.exists(folder(out, "1.0", 32)),
          f"a folder of another case: exit {p.returncode} (expected 2, before any point runs):\n{p.stderr}")
    same(folder(out, "3.0", 64), wrong, "the folder of another case, refused")
    with open(os.path.join(wrong, "summary.json"), "w", encoding="utf-8") as f:
        f.write('{"mine": 1}\n')
    p = sweep(binary, out)
    check(p.returncode == 2 and "not a cmc run summary" in p.stderr and not os.path.exists(folder(out, "1.0", 32)) and
          open(os.path.join(wrong, "summary.json"), encoding="utf-8").read() == '{"mine": 1}\n',
          f"a foreign summary.json: exit {p.returncode} (expected 2, left as it was):\n{p.stderr}")


def dry_run_cpu(binary, work, n):
    """CPU seconds of `cmc sweep --dry-run` over n values of one key, and the process."""
    import resource
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    values = ",".join(str(k) for k in range(1, n + 1))
    p = cmc(binary, "sweep", TABOR, "--out", os.path.join(work, "many"), "--over", f"solver.max_iterations={values}",
            "--dry-run")
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime, p


def test_many_values(binary, work):
    """Checking an --over list takes time linear in its values: 10,000 values, --dry-run, took
    0.9 s of CPU (2,500: 0.25 s) on two busy cores, where one pair check per two values took
    19 s for 4,000. Four times the values must cost less than 8 times the time (quadratic: 16)."""
    small, p = dry_run_cpu(binary, work, 2500)
    check(p.returncode == 0 and p.stdout.count("would run") == 2500, f"2,500 values: exit {p.returncode}\n{p.stderr}")
    large, p = dry_run_cpu(binary, work, 10000)
    check(p.returncode == 0 and p.stdout.count("would run") == 10000, f"10,000 values: exit {p.returncode}\n{p.stderr}")
    check(large < 8 * max(small, 0.05) and large < 10.0,
          f"10,000 values took {large:.2f} s of CPU, 2,500 took {small:.2f} s: not linear")
    check(not os.path.exists(os.path.join(work, "many")), "--dry-run wrote into --out")


def test_folders(binary, work):
    """A link on the way to a point's folder is refused before anything runs, so is a second
    --out, and a point whose checkpoint is damaged says how to start it afresh within the sweep
    (there is no --resume to drop)."""
    out = os.path.join(work, "linked")
    elsewhere = os.path.join(work, "elsewhere")
    for d in (out, elsewhere):
        shutil.rmtree(d, ignore_errors=True)
    os.makedirs(out)
    os.makedirs(elsewhere)
    os.symlink(elsewhere, os.path.join(out, "interaction.tabor_1.0"))
    p = sweep(binary, out)
    check(p.returncode == 2 and "is a symbolic link" in p.stderr and os.listdir(elsewhere) == [],
          f"a linked point folder: exit {p.returncode} (expected 2, nothing written through it):\n{p.stderr}")
    twice = os.path.join(work, "twice")
    p = sweep(binary, os.path.join(work, "once"), "--out", twice)
    check(p.returncode == 2 and "--out is given twice" in p.stderr and not os.path.exists(twice),
          f"--out given twice: exit {p.returncode} (expected 2, nothing written):\n{p.stderr}")
    out = os.path.join(work, "damaged")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(os.path.join(folder(out, "1.0", 32), ".partial"))
    with open(os.path.join(folder(out, "1.0", 32), ".partial", "checkpoint.h5"), "wb") as f:
        f.write(b"not an HDF5 file")
    p = sweep(binary, out)
    check(p.returncode != 0 and "without --resume" not in p.stderr and
          f"remove {os.path.join(folder(out, '1.0', 32), '.partial')} and run the sweep again" in p.stderr,
          f"a damaged checkpoint: exit {p.returncode}, expected advice for a sweep:\n{p.stderr}")


def main(argv):
    tests = {name[len("test_"):]: fn for name, fn in globals().items() if name.startswith("test_")}
    if len(argv) != 3 or argv[2] not in tests:
        print(__doc__, file=sys.stderr)
        return 2
    work = os.path.join(os.path.abspath(argv[1]), argv[2])
    os.makedirs(work, exist_ok=True)
    tests[argv[2]](os.path.abspath(argv[0]), work)
    print(f"sweep_test {argv[2]}: " + (f"{len(failures)} failure(s)" if failures else "passed"))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
