"""The package's version (read by the build, ``pyproject.toml``; re-exported as ``trikedyn.__version__``)."""

__version__ = "0.1.0"
