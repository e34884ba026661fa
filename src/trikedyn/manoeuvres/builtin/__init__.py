"""The built-in manoeuvres, one module each; importing this package registers them all.

Every module in this folder is imported (in name order) and registers itself with
:func:`trikedyn.manoeuvres.registry.register`: a new built-in test is one new file here.
"""

from ...registry import import_submodules

import_submodules(__name__, __path__)
