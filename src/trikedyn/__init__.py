"""trikedyn: stability analysis of three-wheeled electric vehicles."""

__version__ = "0.1.0"
