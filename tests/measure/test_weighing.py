"""Weighing records: reduction from a TOML file, and clear errors."""

import numpy as np
import pytest

from trikedyn.errors import InputError
from trikedyn.measure.cg import tilted_wheel_loads, wheel_loads_from_cg
from trikedyn.measure.weighing import load_weighing, reduce_weighing
from trikedyn.units import STANDARD_GRAVITY as G


def _record(truth=(0.8321, 0.016, 0.3804), mass=583.0):
    contacts = {"front": [1.95, 0.0], "rear_left": [0.0, 0.55], "rear_right": [0.0, -0.55]}
    level = wheel_loads_from_cg(mass, truth[:2], list(contacts.values())) / G
    heights = [0.15, 0.25, 0.35]
    raised = tilted_wheel_loads(mass, truth, 1.95, heights, wheel_radius_m=0.27) / G
    return {
        "reading_std_kg": 0.5,
        "wheel_radius_m": 0.27,
        "contacts": contacts,
        "level": dict(zip(contacts, level.tolist(), strict=True)),
        "tilted": [{"raised": "front", "height_m": h, "raised_axle_kg": f} for h, f in zip(heights, raised.tolist(), strict=True)],
    }


def test_reduce_weighing_round_trip():
    res = reduce_weighing(_record())
    assert res.level.mass_kg == pytest.approx(583.0)
    np.testing.assert_allclose([res.level.cg_x_m, res.level.cg_y_m, res.height.cg_z_m], [0.8321, 0.016, 0.3804], atol=1e-7)


def test_weighing_file_errors(tmp_path):
    rec = _record()
    rec["level"]["rear_left"] = -1.0
    with pytest.raises(InputError, match="level.rear_left: scale reading must be >= 0"):
        reduce_weighing(rec, where="w.toml")
    rec = _record()
    del rec["wheel_radius_m"]
    with pytest.raises(InputError, match="wheel_radius_m"):
        reduce_weighing(rec)
    with pytest.raises(InputError, match="did you mean 'contacts'"):
        reduce_weighing({**_record(), "contact": {}})
    path = tmp_path / "w.toml"
    path.write_text("[level\n")
    with pytest.raises(InputError, match="w.toml"):
        load_weighing(path)
