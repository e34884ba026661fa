"""The built-in tyre models, one module each; importing this package registers them all.

Every module in this folder is imported (in name order) and registers itself with
:func:`trikedyn.tyre.models.register`: a new built-in tyre model is one new file here (plus, if it needs
one, its branch of the compiled :func:`trikedyn.tyre.interface.tyre_forces`).
"""

from ...registry import import_submodules

import_submodules(__name__, __path__)
