"""The sensor's full-scale ranges (gyro_range °/s, acc_range g): clipped samples are counted."""

import numpy as np
import pytest

import clino

RATE = 100.0
REST = 200  # samples at rest before and after the turn (2 s)
TURN = 50  # 0.5 s at 300 °/s about x, read clipped at 250 °/s


def clipped_turn():
    """A level sensor at rest, a 150° turn about x at 300 °/s whose gyro reads
    the 250 °/s rail, then rest: (gyr rad/s, acc m/s²)."""
    n = 2 * REST + TURN
    gyr = np.zeros((n, 3))
    gyr[REST:REST + TURN, 0] = np.radians(250.0)  # what the sensor reads, not the true 300
    # the true angle about x: 0, then 300 °/s for 0.5 s, then held at 150°
    angle = np.radians(300.0) * np.clip(np.arange(n) - REST + 1, 0, TURN) / RATE
    acc = np.column_stack([np.zeros(n), clino.G0 * np.sin(angle), clino.G0 * np.cos(angle)])
    return gyr, acc


def test_clipped_gyro_samples_are_counted():
    gyr, acc = clipped_turn()
    counts = clino.fuse_full(gyr, acc, rate=RATE, gyro_range=250, acc_range=2)["counts"]
    assert counts["samples"] == len(gyr)
    assert counts["gyro_clipped"] == TURN
    assert counts["acc_clipped"] == 0
    # no range given: nothing is taken for clipped
    counts = clino.fuse_full(gyr, acc, rate=RATE)["counts"]
    assert (counts["gyro_clipped"], counts["acc_clipped"]) == (0, 0)


def test_the_filter_class_counts_them_too():
    gyr, acc = clipped_turn()
    f = clino.Dynamic(rate=RATE, gyro_range=250, acc_range=2)
    f.update_batch(gyr, acc)
    assert (f.counts["gyro_clipped"], f.counts["acc_clipped"]) == (TURN, 0)


def test_the_file_path_counts_them(tmp_path):
    gyr, acc = clipped_turn()
    path = tmp_path / "turn.csv"
    clino.write_table(path, {
        "t_s": np.arange(len(gyr)) / RATE,
        **{f"gyr_{x}_rad_s": gyr[:, j] for j, x in enumerate("xyz")},
        **{f"acc_{x}_m_s2": acc[:, j] for j, x in enumerate("xyz")},
    })
    row = clino.summarize(path, gyro_range=250, acc_range=2)
    assert (row["samples"], row["gyro_clipped"], row["acc_clipped"]) == (len(gyr), TURN, 0)


@pytest.mark.parametrize("bad", [0, -1, float("nan"), float("inf")])
def test_a_range_that_is_not_positive_and_finite_is_refused(bad):
    gyr, acc = np.zeros((5, 3)), np.tile([0.0, 0.0, clino.G0], (5, 1))
    with pytest.raises(ValueError, match="gyro_range"):
        clino.fuse(gyr, acc, rate=RATE, gyro_range=bad)
    with pytest.raises(ValueError, match="acc_range"):
        clino.fuse(gyr, acc, rate=RATE, acc_range=bad)
    with pytest.raises(ValueError, match="gyro_range"):
        clino.Filter(rate=RATE, gyro_range=bad)
    with pytest.raises(ValueError, match="acc_range"):
        clino.summarize("never-read.csv", acc_range=bad)
    with pytest.raises(ValueError, match="gyro_range"):
        clino.evaluate([], gyro_range=bad)
