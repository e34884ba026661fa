"""Overrides that make a vehicle nearly rigid, on grippy tyres (test helper for the tip-over closed forms)."""

RIGID_GRIPPY = {
    "mass.cg_y_m": 0.0,
    "suspension.front.stiffness_N_per_m": 5e6,
    "suspension.rear.stiffness_N_per_m": 5e6,
    "suspension.front.damping_Ns_per_m": 2e4,
    "suspension.rear.damping_Ns_per_m": 2e4,
    "tyre.vertical_stiffness_N_per_m": 2e6,
    "tyre.vertical_damping_Ns_per_m": 2e3,
    "tyre.mu_x": 3.0,
    "tyre.mu_y": 3.0,
    "drive.max_power_W": 5e4,
    "drive.max_drive_torque_Nm": 1000.0,
}
"""CG on the centre line, rigid suspension and tyres, friction 3, drive that does not run out."""
