"""Measurement reduction: IMU logs, suspension identification (Eqs. 1-4), centre of gravity."""
