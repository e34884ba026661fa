"""The reference paper's published numbers, kept for comparison only (never used as model inputs).

Source: "Electric Delta Trike Stability Characteristic and Maneuverability Analysis: Experiment and
Multi-Body Dynamic Simulation" (``shared/seed/electric-delta-trike-paper.txt``). Lengths in the paper's
tables are in mm in the paper's own axes, whose x datum is not stated; ``REFERENCE_X_DATUM_M`` is the
reading that the preset ``reference-etrike`` takes (see its ``mass.cg_x_m`` note).
"""

from __future__ import annotations

__all__ = [
    "STUDY_SPEC",
    "BODY_MASS_KG",
    "CG_MM",
    "REFERENCE_X_DATUM_M",
    "TABLE1",
    "TABLE2_SCALES",
    "TABLE3",
    "TOTAL_MASS_KG",
    "TYRE_VERTICAL_DAMPING_NS_PER_M",
    "TYRE_VERTICAL_STIFFNESS_N_PER_M",
]

STUDY_SPEC = "paper"
"""The built-in study spec of the paper's Fig. 10 (``trikedyn/study/specs/paper.toml``; run by
``trikedyn study paper``)."""

TOTAL_MASS_KG = 508.0
"""Prototype total mass M (section 2.1) [kg]."""
BODY_MASS_KG = 485.0
"""Body mass M_B, total less all wheels (section 2.1) [kg]."""
CG_MM = (240.1, 16.0, 380.4)
"""Measured centre of gravity (section 2.1) [mm], paper axes."""

TABLE1 = {
    "front": {"natural_frequency_hz": 2.916, "damping_ratio": 0.20, "stiffness_N_per_m": 80289.0, "damping_Ns_per_m": 183.83},
    "rear": {"natural_frequency_hz": 2.72, "damping_ratio": 0.29, "stiffness_N_per_m": 45787.85, "damping_Ns_per_m": 160.71},
}
"""Table 1 (stiffness at full precision from Table 2) and the natural frequencies of section 2.1."""

TABLE2_SCALES = (0.8, 1.0, 1.2)
"""Table 2: suspension stiffness and damping at 80, 100 and 120 % of Table 1."""

TABLE3 = (
    (0.0, 240.1, 16.0, 380.4),
    (50.0, 185.9, 14.8, 436.8),
    (100.0, 139.7, 13.7, 484.9),
    (150.0, 99.7, 12.8, 526.5),
    (200.0, 64.9, 11.9, 562.7),
)
"""Table 3: freight mass [kg] and centre of gravity x, y, z [mm] in the paper's axes."""

TYRE_VERTICAL_STIFFNESS_N_PER_M = 200e3
TYRE_VERTICAL_DAMPING_NS_PER_M = 75.0

REFERENCE_X_DATUM_M = 0.592
"""Where ``reference-etrike`` reads the paper's x datum: this far ahead of the rear axle [m]."""
