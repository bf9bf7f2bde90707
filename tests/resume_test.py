#!/usr/bin/python3
"""Interruption tests of `cmc run`: a run killed anywhere and resumed with
--resume gives the same results, bit for bit, as a run that was not interrupted; an
unfinished folder says so; one process at a time writes into a folder.

usage: tests/resume_test.py CMC WORKDIR TEST

TEST is one of
  kill_anywhere     SIGKILL at many points of an adhesive load path with pull-off
                    refinement (before the first checkpoint, in a step, between steps,
                    in the refinement, right after a refinement checkpoint, and a chain
                    of kills of the resumed runs themselves) and of a hard-wall run;
                    every resumed run must equal the uninterrupted one bit for bit
                    (scripts/compare_runs.py: every summary.json value but wall-clock
                    times, every result.h5 dataset and attribute)
  D1_pulloff        killed while refining the pull-off: the resumed summary has the
                    uninterrupted run's pull-off
  D2_jump_scale     killed between steps: the resumed steps are the uninterrupted ones
                    (the jump test's running max of |p| is carried on)
  D3_counters       killed between steps: the path's counters (halved steps, jumps) are
                    the whole path's, and progress lines on a terminal number the steps
                    from where the run resumed
  D8_stale_summary  a run killed before its first checkpoint leaves no earlier run's
                    summary.json (nor result.h5) behind, and an INCOMPLETE marker
  inside_step       the quasi-static solver killed between two outer steps of a load step,
                    with checkpoints inside steps (--checkpoint-every 0): the resumed run
                    says it continues inside the step and equals the uninterrupted one bit
                    for bit (one long step, also killed twice in a chain; a step in the
                    middle of a load sweep); with the default interval (600 s) the same kill
                    resumes from the step's start, also bit for bit; a malformed
                    --checkpoint-every is refused (exit 2) before anything is written
  older_checkpoint  a checkpoint written before a key existed (grid.backend removed from its
                    case text): resumed with a warning naming the key, bit for bit; a
                    checkpoint of another case is refused (exit 2) naming the first
                    differing key and both values, and left as it was
  stopping_limit    solver.max_outer_steps changed on resume: a family run killed after
                    outer step 4 and resumed with the limit 6 stops there (exit 3,
                    not_converged, a notice naming the limit) and equals a fresh run with
                    limit 6 bit for bit, also from a checkpoint written before the key
                    existed; a limit the checkpoint has reached (4) is refused (exit 2),
                    the checkpoint untouched
  stopped_run       a run whose quasi-static solve stopped at solver.max_outer_steps keeps its
                    checkpoint: its summary says how to continue (key "continue"); --resume
                    with the same limit leaves the folder as it is (exit 3), with a smaller one
                    is refused (exit 2); with a larger one it goes on and equals a fresh run
                    with that limit bit for bit (one step stopped after 4 of 7 outer steps,
                    continued to 6 and then to the default; a load sweep whose step 1 stops
                    and whose later steps ran from it, continued with fields written)
  observables_only  a run without fields (output.fields=false) but with observables writes
                    result.h5 with each step's observables and nothing else (no heights, no
                    fields, no result.xdmf); killed between steps and resumed, it equals the
                    uninterrupted run bit for bit
  D7_lock           a second cmc run / validate / refine on a folder in use stops at once
                    with exit code 4, naming the folder and the first run's process id,
                    and the first run's results are intact

Runs are stopped deterministically by cmc's test points (solver/cmc/run/TestPoints.hpp:
CMC_TEST_KILL_AT=NAME:N, CMC_TEST_PAUSE_AT, CMC_TEST_TRACE), not by timers, so the test
is reliable on a loaded machine. Exits 0 on success, 1 with the reasons on failure.
"""
import json
import os
import pty
import re
import shutil
import signal
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
PATH_CASE = os.path.join(HERE, "data", "resume_path.toml")  # adhesive load path, 64²
HARDWALL_CASE = os.path.join(ROOT, "cases", "validation", "hertz-free.toml")
QUASI_STATIC_CASE = os.path.join(ROOT, "cases", "challenge", "load-sweep.toml")  # quasi_static, 14 steps
FAMILY_CASE = os.path.join(ROOT, "cases", "challenge", "scaled-family.toml")  # quasi_static, one step, 7 outer at 128²
COMPARE = os.path.join(ROOT, "scripts", "compare_runs.py")

failures = []


def check(ok, message):
    if not ok:
        failures.append(message)
        print("FAIL: " + message, flush=True)
    return ok


def env(**extra):
    e = dict(os.environ)
    for k in ("CMC_TEST_KILL_AT", "CMC_TEST_PAUSE_AT", "CMC_TEST_CONTINUE", "CMC_TEST_TRACE"):
        e.pop(k, None)
    e["CMC_THREADS"] = "1"  # the same bits in every run (the reductions' chunks follow the thread count)
    e.update(extra)
    return e


def cmc_run(cmc, case, out, *args, resume=False, **extra):
    cmd = [cmc, "run", case, "--out", out, "--quiet", *args] + (["--resume"] if resume else [])
    return subprocess.run(cmd, env=env(**extra), capture_output=True, text=True)


def killed(p):
    return p.returncode == -signal.SIGKILL


def compare(a, b, label):
    p = subprocess.run(["/usr/bin/python3", COMPARE, a, b], capture_output=True, text=True)
    return check(p.returncode == 0, f"{label}: {b} differs from the uninterrupted run {a}:\n{p.stdout}{p.stderr}")


def summary(folder):
    with open(os.path.join(folder, "summary.json")) as f:
        return json.load(f)


def reference(cmc, work, case=PATH_CASE, *args, name="reference"):
    """The uninterrupted run, and the test points it passed, in order."""
    out = os.path.join(work, name)
    shutil.rmtree(out, ignore_errors=True)
    p = cmc_run(cmc, case, out, *args, CMC_TEST_TRACE="1")
    if p.returncode != 0:
        raise SystemExit(f"resume_test: the uninterrupted run failed ({p.returncode}):\n{p.stderr}")
    trace = re.findall(r"^cmc: test point (\w+):(\d+)$", p.stderr, re.M)
    return out, [(n, int(k)) for n, k in trace]


def points(trace):
    """The solves of each step, and those after the last step (refining the pull-off)."""
    steps, current = [], []
    for name, n in trace:
        if name == "solve":
            current.append(n)
        elif name == "step":
            steps.append(current)
            current = []
    return steps, current


def interrupted(cmc, case, out, point, *args, resume=False, marker=True):
    """A run (or a resumed run) killed at `point`: True if it died of SIGKILL. With `marker`,
    also checks that the folder says it is unfinished (D8; the D1-D3 tests leave it out,
    so that each fails for its own defect only)."""
    p = cmc_run(cmc, case, out, *args, resume=resume, CMC_TEST_KILL_AT=point)
    ok = check(killed(p), f"kill at {point}: expected the run to die of SIGKILL, got exit {p.returncode}:\n{p.stderr}")
    if ok and marker:
        check(not os.path.exists(os.path.join(out, "summary.json")),
              f"kill at {point}: {out}/summary.json exists in an unfinished folder")
        check(os.path.exists(os.path.join(out, "INCOMPLETE")), f"kill at {point}: {out}/INCOMPLETE is missing")
    return ok


def resume(cmc, case, out, *args):
    p = cmc_run(cmc, case, out, *args, resume=True)
    check(p.returncode == 0, f"resume of {out}: exit {p.returncode}:\n{p.stderr}")
    check(not os.path.exists(os.path.join(out, "INCOMPLETE")) and not os.path.exists(os.path.join(out, ".partial")),
          f"resume of {out}: INCOMPLETE or .partial/ left in a finished folder")
    return p


def path_points(cmc, work):
    ref, trace = reference(cmc, work)
    steps, refinement = points(trace)
    s = summary(ref)
    # The case must exercise what the tests claim to test.
    assert len(steps) == len(s["steps"]), (steps, len(s["steps"]))
    assert s["load_path"]["halved_steps"] > 0 and s["load_path"]["jumps"] > 0, s["load_path"]
    assert len(refinement) >= 4, f"the case refines the pull-off in {len(refinement)} solves, the test needs 4"
    return ref, steps, refinement


def kill_once_and_resume(cmc, work, case, name, point, label):
    """A 64² run of `case` killed at `point`, resumed, and compared with an uninterrupted one."""
    args = ["--set", "grid.n=64"]
    ref, _ = reference(cmc, work, case, *args, name=f"{name}-reference")
    out = os.path.join(work, f"k-{name}")
    shutil.rmtree(out, ignore_errors=True)
    if interrupted(cmc, case, out, point, *args):
        resume(cmc, case, out, *args)
        compare(ref, out, f"{label}, resumed")


def test_kill_anywhere(cmc, work):
    t0 = time.monotonic()
    ref, steps, refinement = path_points(cmc, work)
    longest = max(range(len(steps)), key=lambda k: len(steps[k]))
    assert len(steps[longest]) >= 3, "no step of the case is halved into three solves or more"
    scenarios = {
        "before the first checkpoint": ["solve:1"],
        f"in step {longest} (its solve {len(steps[longest]) // 2 + 1} of {len(steps[longest])})":
            [f"solve:{steps[longest][len(steps[longest]) // 2]}"],
        f"between steps {len(steps) // 2 - 1} and {len(steps) // 2}": [f"step:{len(steps) // 2}"],
        "in the pull-off refinement (its third solve)": [f"solve:{refinement[2]}"],
        "right after a refinement checkpoint": ["refine:3"],
        "after the last step, before the refinement": [f"step:{len(steps)}"],
        # The resumed runs killed in turn (counts restart in every process).
        "a chain: between steps, then in a step, the refinement, before a first new solve":
            ["step:2", "solve:4", "refine:1", "solve:1"],
    }
    for label, kills in scenarios.items():
        out = os.path.join(work, "k-" + re.sub(r"\W+", "-", label).strip("-"))
        shutil.rmtree(out, ignore_errors=True)
        ok = True
        for i, point in enumerate(kills):
            ok = ok and interrupted(cmc, PATH_CASE, out, point, resume=i > 0)
        if ok:
            resume(cmc, PATH_CASE, out)
            compare(ref, out, f"killed {label} ({' then '.join(kills)}), resumed")
    # Polonsky–Keer (hard wall, three force steps): killed in its second step, resumed.
    kill_once_and_resume(cmc, work, HARDWALL_CASE, "hardwall", "solve:2", "hard wall killed in step 1")
    # The quasi-static solver (the challenge's load sweep at 64², 14 loading steps): killed
    # in its fifth step, resumed.
    kill_once_and_resume(cmc, work, QUASI_STATIC_CASE, "quasi-static", "solve:5",
                         "quasi-static load sweep killed in step 4")
    print(f"kill_anywhere: {len(scenarios) + 2} interrupted runs resumed in {time.monotonic() - t0:.1f} s")


def test_D1_pulloff(cmc, work):
    ref, steps, refinement = path_points(cmc, work)
    out = os.path.join(work, "d1")
    shutil.rmtree(out, ignore_errors=True)
    if interrupted(cmc, PATH_CASE, out, f"solve:{refinement[2]}", marker=False):
        resume(cmc, PATH_CASE, out)
        got, want = summary(out).get("load_path", {}), summary(ref)["load_path"]
        for key in ("pulloff_force", "pulloff_mean_pressure", "pulloff_branch"):
            check(got.get(key) == want[key], f"killed while refining the pull-off, resumed: load_path.{key} = "
                                             f"{got.get(key)!r}, uninterrupted {want[key]!r}")


def steps_after(folder, first):
    keys = ("index", "branch", "mean_pressure", "contact_fraction", "penetration", "halvings", "jump", "iterations")
    return [{k: s[k] for k in keys} for s in summary(folder)["steps"][first:]]


def test_D2_jump_scale(cmc, work):
    ref, steps, _ = path_points(cmc, work)
    # Killed after step 3: on unloading, where |p| has fallen below its running max.
    out = os.path.join(work, "d2")
    shutil.rmtree(out, ignore_errors=True)
    if interrupted(cmc, PATH_CASE, out, "step:4", marker=False):
        resume(cmc, PATH_CASE, out)
        for want, got in zip(steps_after(ref, 4), steps_after(out, 4)):
            check(want == got, f"killed after step 3, resumed: step {want['index']} differs:\n"
                               f"  uninterrupted {want}\n  resumed       {got}")


def run_on_terminal(cmd, environment):
    """Runs cmd with stderr on a pseudo-terminal (cmc prints progress only to one)."""
    master, slave = pty.openpty()
    p = subprocess.Popen(cmd, env=environment, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=slave)
    os.close(slave)
    chunks = []
    while True:
        try:
            data = os.read(master, 4096)
        except OSError:  # EIO: the child closed the terminal
            break
        if not data:
            break
        chunks.append(data)
    os.close(master)
    p.wait()
    return p.returncode, b"".join(chunks).decode(errors="replace")


def test_D3_counters(cmc, work):
    ref, steps, _ = path_points(cmc, work)
    out = os.path.join(work, "d3")
    shutil.rmtree(out, ignore_errors=True)
    if not interrupted(cmc, PATH_CASE, out, "step:2", marker=False):
        return
    rc, text = run_on_terminal([cmc, "run", PATH_CASE, "--out", out, "--resume"], env())
    check(rc == 0, f"resume of {out} on a terminal: exit {rc}:\n{text}")
    want, got = summary(ref)["load_path"], summary(out).get("load_path", {})
    for key in ("halved_steps", "jumps"):
        check(got.get(key) == want[key], f"killed after step 1, resumed: load_path.{key} = {got.get(key)!r}, "
                                         f"uninterrupted {want[key]!r}")
    shown = [int(k) for k in re.findall(r"\bstep (\d+)/\d+ +iteration", text)]
    check(bool(shown), f"no progress lines on the terminal:\n{text}")
    check(shown and min(shown) == 2, f"killed after step 1, resumed: progress lines show steps {sorted(set(shown))}, "
                                     "expected them to start at step 2")


def test_D8_stale_summary(cmc, work):
    out = os.path.join(work, "d8")
    shutil.rmtree(out, ignore_errors=True)
    p = cmc_run(cmc, PATH_CASE, out)
    check(p.returncode == 0 and os.path.exists(os.path.join(out, "summary.json")), f"first run: exit {p.returncode}")
    # Another run in the same folder, killed before its first checkpoint.
    args = ["--set", "solver.tolerance=1e-5"]
    p = cmc_run(cmc, PATH_CASE, out, *args, CMC_TEST_KILL_AT="solve:1")
    check(killed(p), f"second run: expected SIGKILL, got exit {p.returncode}")
    for f in ("summary.json", "result.h5", "result.xdmf"):
        check(not os.path.exists(os.path.join(out, f)),
              f"a run killed before its first checkpoint left the earlier run's {f} in {out}")
    marker = os.path.join(out, "INCOMPLETE")
    check(os.path.exists(marker) and "--resume" in open(marker).read(),
          f"{marker}: missing, or it does not say how to continue the run")


def test_inside_step(cmc, work):
    every0 = ["--checkpoint-every", "0"]
    cases = {  # label: (case, grid, kills, options of the killed runs)
        "one step of 7 outer steps, killed after outer step 4": (FAMILY_CASE, 128, ["outer:4"], every0),
        "the same, its resumed run killed again after 2 more": (FAMILY_CASE, 128, ["outer:4", "outer:2"], every0),
        "load sweep, killed inside step 6": (QUASI_STATIC_CASE, 64, ["outer:9"], every0),
        "load sweep, default interval: from step 6's start": (QUASI_STATIC_CASE, 64, ["outer:9"], []),
    }
    refs = {}
    for label, (case, n, kills, extra) in cases.items():
        args = ["--set", f"grid.n={n}"]
        if case not in refs:
            ref, trace = reference(cmc, work, case, *args, "--checkpoint-every", "0",
                                   name=os.path.basename(case).split(".")[0] + "-reference")
            refs[case] = ref, sum(1 for name, _ in trace if name == "outer")
        need = sum(int(k.split(":")[1]) for k in kills)
        assert refs[case][1] > need, f"{case} at {n}²: {refs[case][1]} outer-step test points, the test needs {need}"
        out = os.path.join(work, "k-" + re.sub(r"\W+", "-", label).strip("-"))
        shutil.rmtree(out, ignore_errors=True)
        ok = True
        for i, point in enumerate(kills):
            ok = ok and interrupted(cmc, case, out, point, *args, *extra, resume=i > 0)
        if not ok:
            continue
        # Resumed without --quiet: it says where it goes on from.
        p = subprocess.run([cmc, "run", case, "--out", out, "--resume", *args], env=env(), capture_output=True,
                           text=True)
        said = re.search(r"^resuming .*$", p.stderr, re.M)
        if not check(p.returncode == 0 and said is not None,
                     f"{label}: the resumed run exited {p.returncode} or did not say it resumed:\n{p.stderr}"):
            continue
        check(("inside" in said.group(0)) == bool(extra),
              f"{label}: expected the resumed run to go on {'inside the step' if extra else 'from the step start'}, "
              f"it said: {said.group(0)!r}")
        compare(refs[case][0], out, f"{label}: killed at {' then '.join(kills)}, resumed")
    # Bad input: refused before anything is written.
    for bad in ("-1", "soon", "nan"):
        out = os.path.join(work, "bad-every")
        shutil.rmtree(out, ignore_errors=True)
        p = cmc_run(cmc, FAMILY_CASE, out, "--set", "grid.n=64", "--checkpoint-every", bad)
        check(p.returncode == 2 and "--checkpoint-every" in p.stderr and not os.path.exists(out),
              f"--checkpoint-every {bad}: exit {p.returncode} (expected 2, a message naming the option, no "
              f"folder):\n{p.stderr}")


def edit_checkpoint_case(folder, edit):
    """Rewrite the case text kept in FOLDER's checkpoint with edit(text)."""
    import h5py
    import numpy
    with h5py.File(os.path.join(folder, ".partial", "checkpoint.h5"), "r+") as f:
        text = f["progress"][()].decode()
        new = edit(text)
        assert new != text, "edit_checkpoint_case: the edit changed nothing"
        del f["progress"]
        b = new.encode()
        f.create_dataset("progress", data=numpy.array(b, dtype=f"S{len(b) + 1}"))


def test_older_checkpoint(cmc, work):
    args = ["--set", "grid.n=128", "--checkpoint-every", "0"]
    ref, _ = reference(cmc, work, FAMILY_CASE, *args)
    out = os.path.join(work, "older")
    shutil.rmtree(out, ignore_errors=True)
    if not interrupted(cmc, FAMILY_CASE, out, "outer:4", *args):
        return
    # As a version of cmc before grid.backend wrote it.
    edit_checkpoint_case(out, lambda t: re.sub(r'\n\s*"backend" : "cpu",', "", t))
    p = subprocess.run([cmc, "run", FAMILY_CASE, "--out", out, "--resume", *args], env=env(), capture_output=True,
                       text=True)
    if check(p.returncode == 0, f"older checkpoint: the resumed run exited {p.returncode}:\n{p.stderr}"):
        check(re.search(r"warning: .*predates the key grid\.backend = \"cpu\"", p.stderr) is not None
              and re.search(r"^resuming .*inside", p.stderr, re.M) is not None,
              f"older checkpoint: expected a warning naming grid.backend and a resume inside the step:\n{p.stderr}")
        compare(ref, out, "older checkpoint, resumed")
    # Another case's checkpoint (its grid edited to 64): refused, the key named, nothing touched.
    out = os.path.join(work, "other")
    shutil.rmtree(out, ignore_errors=True)
    if not interrupted(cmc, FAMILY_CASE, out, "outer:4", *args):
        return
    edit_checkpoint_case(out, lambda t: t.replace('"n" : 128', '"n" : 64'))
    before = os.path.getmtime(os.path.join(out, ".partial", "checkpoint.h5"))
    p = cmc_run(cmc, FAMILY_CASE, out, *args, resume=True)
    check(p.returncode == 2 and "key grid.n: 64 in the checkpoint, 128 here" in p.stderr,
          f"another case's checkpoint: exit {p.returncode} (expected 2, naming grid.n and both values):\n{p.stderr}")
    check(os.path.getmtime(os.path.join(out, ".partial", "checkpoint.h5")) == before,
          "another case's checkpoint: the refused resume touched it")


def test_stopping_limit(cmc, work):
    args = ["--set", "grid.n=128", "--checkpoint-every", "0"]
    limit = ["--set", "solver.max_outer_steps=6"]
    # The run a fresh process makes with the limit: it stops unconverged after 6 of its 7 outer steps.
    ref = os.path.join(work, "reference-limit-6")
    shutil.rmtree(ref, ignore_errors=True)
    p = cmc_run(cmc, FAMILY_CASE, ref, *args, *limit)
    if not check(p.returncode == 3, f"fresh run with limit 6: exit {p.returncode}, expected 3:\n{p.stderr}"):
        return
    step = summary(ref)["steps"][0]
    if not check(not step["converged"] and "after 6 outer steps" in step["message"],
                 f"fresh run with limit 6: expected an unconverged step stopped after 6 outer steps: {step}"):
        return
    for label, edit in (("the key in the checkpoint", None),
                        ("a checkpoint from before the key",
                         lambda t: re.sub(r'\n\s*"max_outer_steps" : 1000,?', "", t))):
        out = os.path.join(work, "limit-" + ("old" if edit else "now"))
        shutil.rmtree(out, ignore_errors=True)
        if not interrupted(cmc, FAMILY_CASE, out, "outer:4", *args):
            return
        if edit:
            edit_checkpoint_case(out, edit)
        p = subprocess.run([cmc, "run", FAMILY_CASE, "--out", out, "--resume", *args, *limit], env=env(),
                           capture_output=True, text=True)
        if check(p.returncode == 3, f"{label}, resumed with limit 6: exit {p.returncode}, expected 3:\n{p.stderr}"):
            check(re.search(r"warning: .*stopping limit, solver\.max_outer_steps: 1000 .*in the checkpoint, 6 here",
                            p.stderr) is not None,
                  f"{label}, resumed with limit 6: expected a notice naming the limit and both values:\n{p.stderr}")
            compare(ref, out, f"{label}, resumed with limit 6")
    # A limit the step under way has reached (4 outer steps made): refused, nothing touched.
    out = os.path.join(work, "limit-reached")
    shutil.rmtree(out, ignore_errors=True)
    if not interrupted(cmc, FAMILY_CASE, out, "outer:4", *args):
        return
    before = os.path.getmtime(os.path.join(out, ".partial", "checkpoint.h5"))
    p = cmc_run(cmc, FAMILY_CASE, out, *args, "--set", "solver.max_outer_steps=4", resume=True)
    check(p.returncode == 2 and "solver.max_outer_steps = 4 cannot continue" in p.stderr
          and "has made 4 outer steps" in p.stderr,
          f"a limit already reached: exit {p.returncode} (expected 2, naming the limit and the steps made):\n{p.stderr}")
    check(os.path.getmtime(os.path.join(out, ".partial", "checkpoint.h5")) == before,
          "a limit already reached: the refused resume touched the checkpoint")


def test_stopped_run(cmc, work):
    def fresh(case, name, *args):
        out = os.path.join(work, name)
        shutil.rmtree(out, ignore_errors=True)
        p = cmc_run(cmc, case, out, *args)
        check(p.returncode in (0, 3), f"{name}: exit {p.returncode}:\n{p.stderr}")
        return out

    def kept(out):
        return os.path.exists(os.path.join(out, ".partial", "checkpoint.h5"))

    grid = ["--set", "grid.n=128"]
    limit = lambda m: ["--set", f"solver.max_outer_steps={m}"]  # noqa: E731
    ref6, ref = fresh(FAMILY_CASE, "limit-6", *grid, *limit(6)), fresh(FAMILY_CASE, "default", *grid)
    out = fresh(FAMILY_CASE, "stopped", *grid, *limit(4))
    s = summary(out)
    if not check(s["status"] == "not_converged" and "after 4 outer steps" in s["steps"][0]["message"]
                 and s.get("continue", {}).get("max_outer_steps") == 4 and "--resume" in s["continue"].get("how", "")
                 and kept(out) and not os.path.exists(os.path.join(out, "INCOMPLETE")),
                 f"a run stopped at limit 4: expected not_converged, a 'continue' record, a kept checkpoint and no "
                 f"INCOMPLETE: {s.get('continue')}, {os.listdir(out)}"):
        return
    stamps = lambda: [os.path.getmtime(os.path.join(out, f)) for f in ("summary.json", ".partial/checkpoint.h5")]  # noqa: E731
    before = stamps()
    p = cmc_run(cmc, FAMILY_CASE, out, *grid, *limit(4), resume=True)
    check(p.returncode == 3 and "left as it is" in p.stderr and stamps() == before,
          f"resumed with the limit it stopped at: exit {p.returncode} (expected 3, the folder untouched):\n{p.stderr}")
    p = cmc_run(cmc, FAMILY_CASE, out, *grid, *limit(3), resume=True)
    check(p.returncode == 2 and "a smaller limit cannot continue it" in p.stderr and stamps() == before,
          f"resumed with a smaller limit: exit {p.returncode} (expected 2, the folder untouched):\n{p.stderr}")
    # Without --quiet: it says where it goes on from, the point before the last allowed outer
    # step (written whatever --checkpoint-every says), so only that step is redone.
    p = subprocess.run([cmc, "run", FAMILY_CASE, "--out", out, "--resume", *grid, *limit(6)], env=env(),
                       capture_output=True, text=True)
    check("step 0 inside: 3 outer steps" in p.stderr,
          f"continued to limit 6: expected it to resume inside step 0 after 3 outer steps:\n{p.stderr}")
    if check(p.returncode == 3, f"continued to limit 6: exit {p.returncode}, expected 3:\n{p.stderr}"):
        compare(ref6, out, "stopped at 4, continued to limit 6")
        check(kept(out), "continued to limit 6 and stopped again: its checkpoint is not kept")
    resume(cmc, FAMILY_CASE, out, *grid)
    compare(ref, out, "stopped at 4, continued to 6, then to the default limit")

    # A load sweep: step 1 stops at limit 2, the later steps run from its state (and stop or
    # not); the checkpoint stays the one from before step 1, without the later steps' fields.
    fields = grid + ["--set", "output.fields=true"]
    ref = fresh(QUASI_STATIC_CASE, "sweep-default", *fields)
    out = fresh(QUASI_STATIC_CASE, "sweep-stopped", *fields, *limit(2))
    s = summary(out)
    stopped = [st["index"] for st in s["steps"] if not st["converged"]]
    if not check(stopped and stopped[0] == 1 and len(s["steps"]) == 14 and s["continue"]["step"] == 1 and kept(out),
                 f"load sweep at limit 2: expected step 1 to stop first, all 14 steps run, the checkpoint kept: "
                 f"{stopped}, {s.get('continue')}"):
        return
    left = sorted(f for f in os.listdir(os.path.join(out, ".partial")) if f.startswith("step_"))
    check(left == ["step_0000.h5"], f"load sweep at limit 2: the kept .partial/ holds {left}, expected step 0's only")
    resume(cmc, QUASI_STATIC_CASE, out, *fields)
    compare(ref, out, "load sweep stopped at limit 2, continued to the default limit")


def test_observables_only(cmc, work):
    import h5py
    case = os.path.join(ROOT, "cases", "challenge", "load-sweep-hardwall.toml")
    args = ["--set", "grid.n=64", "--set", "loading.values=[1e5,2.5e5,5e5]", "--set", "output.fields=false"]
    ref, _ = reference(cmc, work, case, *args, name="observables-reference")
    check(not os.path.exists(os.path.join(ref, "result.xdmf")), "a run without fields wrote result.xdmf")
    with h5py.File(os.path.join(ref, "result.h5"), "r") as f:
        check("heights" not in f, "a run without fields wrote the heights into result.h5")
        for k in range(3):
            g = f"step_{k:04d}"
            check(f"{g}/observables/gap_hist_density" in f and f"{g}/observables/stress_spectrum_C" in f,
                  f"result.h5 has no observables for {g}")
            check(f"{g}/pressure" not in f, f"a run without fields wrote {g}/pressure")
    out = os.path.join(work, "k-observables")
    shutil.rmtree(out, ignore_errors=True)
    if interrupted(cmc, case, out, "step:2", *args):
        resume(cmc, case, out, *args)
        compare(ref, out, "a run without fields killed between steps 1 and 2, resumed")


def test_D7_lock(cmc, work):
    ref, _ = reference(cmc, work)
    out = os.path.join(work, "d7")
    shutil.rmtree(out, ignore_errors=True)
    go = os.path.join(work, "d7-continue")
    if os.path.exists(go):
        os.remove(go)
    first = subprocess.Popen([cmc, "run", PATH_CASE, "--out", out, "--quiet"], stderr=subprocess.PIPE, text=True,
                             env=env(CMC_TEST_PAUSE_AT="step:2", CMC_TEST_CONTINUE=go))
    try:
        line = first.stderr.readline()  # blocks until the first run holds the folder, paused
        m = re.match(r"cmc: test point step:2: paused, pid (\d+)", line)
        if not check(m is not None, f"the first run did not pause: {line!r}"):
            return
        pid = m.group(1)
        before = {f: os.path.getmtime(os.path.join(out, f)) for f in os.listdir(out)}
        validation_case = os.path.join(ROOT, "cases", "validation", "maugis-dugdale-lambda1.toml")
        seconds = []
        for cmd in ([cmc, "run", PATH_CASE, "--out", out],
                    [cmc, "run", PATH_CASE, "--out", out, "--resume"],
                    # validate writes (and locks) --out/<case name>: name the case after the folder
                    [cmc, "validate", validation_case, "--set", "grid.n=64", "--set", 'case.name="d7"', "--out", work],
                    [cmc, "refine", HARDWALL_CASE, "--grids", "32", "64", "--out", out]):
            t = time.monotonic()
            p = subprocess.run(cmd, env=env(), capture_output=True, text=True, timeout=120)
            seconds.append(time.monotonic() - t)
            label = " ".join(os.path.basename(c) for c in cmd[1:3])
            check(p.returncode == 4, f"{label} on a folder in use: exit {p.returncode}, expected 4:\n{p.stderr}")
            check(out in p.stderr and f"pid {pid}" in p.stderr,
                  f"{label} on a folder in use: the message does not name {out} and pid {pid}:\n{p.stderr}")
        check(max(seconds) < 30, f"a second run took {max(seconds):.1f} s to stop (expected at once)")
        after = {f: os.path.getmtime(os.path.join(out, f)) for f in os.listdir(out)}
        check(before == after, f"the second runs changed the first's folder:\n  before {before}\n  after  {after}")
    finally:
        open(go, "w").close()
        rest = first.stderr.read()
        first.wait(timeout=300)
    check(first.returncode == 0, f"the first run, continued: exit {first.returncode}:\n{rest}")
    compare(ref, out, "the first run, after the second ones were turned away")


def main(argv):
    if len(argv) != 3 or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 2
    cmc, work, test = os.path.abspath(argv[0]), os.path.abspath(argv[1]), argv[2]
    fn = globals().get("test_" + test)
    if fn is None:
        print(f"resume_test: unknown test {test!r} (see --help)", file=sys.stderr)
        return 2
    work = os.path.join(work, test)
    os.makedirs(work, exist_ok=True)
    fn(cmc, work)
    if failures:
        print(f"resume_test {test}: {len(failures)} failure(s)")
        return 1
    print(f"resume_test {test}: passed")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
