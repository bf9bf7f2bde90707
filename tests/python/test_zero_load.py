"""cmc.solve at zero and tiny loads: the answer does not depend on where the heights' zero lies
(a constant added to the heights moves the penetration, nothing else)."""
import numpy as np
import pytest



def rough(n=32, seed=3):
    """A small random surface (m), zero mean, rms about 1 µm."""
    h = np.random.default_rng(seed).normal(0.0, 1e-6, (n, n))
    return h - h.mean()


@pytest.mark.parametrize("pressure", [0.0, 1e-3])
def test_zero_and_tiny_loads_do_not_depend_on_the_heights_offset(cmc, pressure):
    """Three offsets: zero mean, every height <= 0, every height > 0. The contact fraction, the
    mean gap and the gap field are the same for each (the penetration moves with the offset).
    Measured: the mean gap and the gap field agree to 6e-16 relative, the penetration to 4e-22 m
    at 1 mPa (exactly at 0): bounds 1e-12 and 1e-15 m. Before, at 0 Pa the contact fraction was
    0.5, 1 or 0 by offset."""
    h = rough()
    answers = []
    for offset in (0.0, -h.max(), 1e-5 - h.min()):
        s = cmc.solve(h + offset, 1e-4, 25e6, pressure=pressure)
        assert s.converged, s.message
        answers.append(s)
        assert s.penetration == pytest.approx(answers[0].penetration + offset, abs=1e-15)
    for s in answers[1:]:
        assert s.contact_fraction == answers[0].contact_fraction
        assert s.mean_gap == pytest.approx(answers[0].mean_gap, rel=1e-12)
        assert np.max(np.abs(s.gap - answers[0].gap)) <= 1e-12 * np.max(answers[0].gap)
    # At zero load the indenter rests on its lowest point: one point of 32² in contact.
    if pressure == 0.0:
        assert answers[0].contact_fraction == 1 / 32 ** 2
        assert answers[0].mean_gap == pytest.approx(h.mean() - h.min(), rel=1e-12)
