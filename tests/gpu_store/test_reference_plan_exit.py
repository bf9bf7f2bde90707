"""scripts/gpu/reference_plan.py exits non-zero when its results cannot be, or were not, saved:
an archive folder that does not exist and a pack without env.sh are refused before anything
runs (exit 2); a plan whose every stage failed says that nothing was saved (exit 1)."""
import os
import stat
import subprocess
import sys

from hostile import ROOT

PLAN = os.path.join(ROOT, "scripts", "gpu", "reference_plan.py")


def pack(tmp, cmc_text="#!/bin/sh\nexit 1\n", env=True):
    """A pack whose cmc is a script (by default one that fails at once)."""
    p = os.path.join(tmp, "pack")
    os.makedirs(os.path.join(p, "bin"))
    with open(os.path.join(p, "bin", "cmc"), "w") as f:
        f.write(cmc_text)
    os.chmod(os.path.join(p, "bin", "cmc"), stat.S_IRWXU)
    if env:
        open(os.path.join(p, "env.sh"), "w").close()
    return p


def plan(tmp, p, tar):
    work = os.path.join(tmp, "work")
    r = subprocess.run([sys.executable, PLAN, "--scale", "64", "--cpu", "--deadline", "60", "--pack", p,
                        "--work", work, "--tar", tar], capture_output=True, text=True, cwd=ROOT,
                       env=dict(os.environ, CMC_THREADS="1"), timeout=240)
    return r, work


def test_archive_into_a_missing_folder_is_refused(tmp_path):
    tmp = str(tmp_path)
    r, work = plan(tmp, pack(tmp), os.path.join(tmp, "no", "such", "plan.tgz"))
    assert r.returncode == 2, r.stdout + r.stderr
    assert "--tar" in r.stderr and "does not exist" in r.stderr
    assert not os.path.exists(work), "a stage ran though its results could not be saved"


def test_pack_without_env_sh_is_refused(tmp_path):
    tmp = str(tmp_path)
    r, work = plan(tmp, pack(tmp, env=False), os.path.join(tmp, "plan.tgz"))
    assert r.returncode == 2, r.stdout + r.stderr
    assert "env.sh" in r.stderr
    assert not os.path.exists(work)


def test_plan_whose_every_stage_failed_says_nothing_was_saved(tmp_path):
    tmp = str(tmp_path)
    tar = os.path.join(tmp, "plan.tgz")
    r, _ = plan(tmp, pack(tmp), tar)
    assert r.returncode == 1, r.stdout + r.stderr
    assert "nothing was saved" in r.stderr
