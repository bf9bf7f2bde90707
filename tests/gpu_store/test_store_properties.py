"""Property tests of scripts/gpu/ingest.py (hypothesis, a fixed seed and a bounded number of
examples): whatever archive it is given (names, dates, modes and numbers drawn from valid and
hostile ones), it ends with exit 0 or 2 and no traceback, writes nothing outside the store,
the references and the results folder (nothing at all when it refuses), stores no impossible
value and writes no file with more than plain modes."""
import json
import os
import stat
import tempfile

from hypothesis import HealthCheck, given, settings, strategies as st
from hypothesis.configuration import set_hypothesis_home_dir

set_hypothesis_home_dir(os.path.join(tempfile.gettempdir(), "cmc-hypothesis"))  # its caches, not in the tree

from hostile import A_R, MEAN_GAP, ingest, plan_archive, scratch_repo, snapshot, summary

from cmc.analysis import plausibility  # noqa: E402

EXAMPLES = 12  # each ingest is a few seconds (best estimates and references rebuilt)

def mostly(valid, hostile):
    """Valid values three times in four, so that some archives pass and test what is stored."""
    return st.one_of(valid, valid, valid, hostile)


names = mostly(st.sampled_from(["cuda-hardwall-32768", "cuda-hardwall-64", "cuda-hardwall-128"]),
               st.one_of(st.sampled_from(["..", ".", "../x", "/abs", "a b", ".partial", "cuda-hardwall-", "x/y",
                                          "rerun-a", "cpu-hardwall-64"]),
                         st.text(alphabet="abc-_./ 019", min_size=1, max_size=12)))
dates = mostly(st.just("2026-01-02"),
               st.one_of(st.sampled_from(["2026-02-30", "/tmp", "../../..", "", "2026-01-02/..", "1-2-3"]),
                         st.text(alphabet="0123456789-/.a", max_size=12)))
numbers = mostly(st.sampled_from([A_R, A_R * 1.0001, A_R * 0.9999]),
                 st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.floats(0.0, 1.0),
                           st.sampled_from([0.5, 0.03, -0.02, 1.7, 0.0])))
gaps = mostly(st.just(MEAN_GAP), st.one_of(st.floats(allow_nan=True, allow_infinity=True),
                                           st.sampled_from([-1e-7, 0.0])))
statuses = mostly(st.just("converged"), st.sampled_from(["not_converged", "failed"]))
modes = mostly(st.sampled_from([0o644, 0o600, 0o777]), st.sampled_from([0o4755, 0o2755, 0o1777]))


@st.composite
def archives(draw):
    runs = []
    for _ in range(draw(st.integers(1, 2))):
        tag = draw(names)
        n = int(tag.split("-")[-1]) if tag.split("-")[-1].isdigit() else 0
        n = n or draw(st.sampled_from([64, 32768]))
        runs.append((tag, summary(n, draw(numbers), mean_gap=draw(gaps), status=draw(statuses))))
    extra = [(f"plan/runs/{runs[0][0]}/{draw(names)}", "x", draw(modes)) for _ in range(draw(st.integers(0, 2)))]
    return runs, draw(dates), extra


def _no_nan(text):
    def refuse(c):
        raise ValueError(f"{c} in the store")
    return json.loads(text, parse_constant=refuse)


@settings(max_examples=EXAMPLES, derandomize=True, deadline=None, database=None,
          suppress_health_check=[HealthCheck.too_slow])
@given(archives())
def test_no_archive_breaks_out_or_fools_the_store(spec):
    runs, date, extra = spec
    with tempfile.TemporaryDirectory(prefix="cmc-store-property-") as tmp:
        ref = scratch_repo(tmp)
        archive = plan_archive(os.path.join(tmp, "plan.tgz"), runs, date=date, extra=extra)
        before = snapshot(tmp)
        r = ingest(tmp, archive)
        assert r.returncode in (0, 2), r.stdout + r.stderr
        assert "Traceback" not in r.stderr, r.stderr
        after = snapshot(tmp)
        if r.returncode == 2:
            assert after == before, "a refused archive changed files"
            return
        inside = (os.path.join("scratch", "ref") + os.sep, os.path.join("scratch", "results") + os.sep)
        for path in set(before) | set(after):
            if not path.startswith(inside) and path not in (os.path.join("scratch", "ref"),
                                                            os.path.join("scratch", "results")):
                assert before.get(path) == after.get(path), f"{path} changed outside the store"
        for path, (mode, digest) in after.items():
            if path.startswith(inside[1]):
                assert stat.S_IMODE(mode) == (0o644 if digest else 0o755), f"{path}: {stat.S_IMODE(mode):04o}"
        with open(os.path.join(ref, "runs.json")) as f:
            records = _no_nan(f.read())["records"]
        for rec in records:
            assert plausibility.record_problems(rec) == [], rec["tag"]
