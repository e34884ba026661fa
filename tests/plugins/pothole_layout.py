"""An IMU log layout from outside the package: ``#POTHOLE-T[ms];Gz[g]`` (time in ms, vertical acceleration in g)."""

from trikedyn.measure import formats

NAME = "test-pothole"


@formats.register
class PotholeLayout(formats.TableFormat):
    """A made-up logger's semicolon table."""

    name = NAME
    description = "made-up pothole logger (test plug-in)"
    sep = ";"
    columns = {"#POTHOLE-T[ms]": ("time_s", 1e-3), "Gz[g]": ("az_mps2", 9.80665)}
