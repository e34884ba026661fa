"""The command groups of ``trikedyn``, one module each; :mod:`trikedyn.cli` maps them and holds the one
error boundary. The modules import only typer and the standard library when loaded: the heavy parts load
inside each command, so ``trikedyn --help`` answers at once."""
