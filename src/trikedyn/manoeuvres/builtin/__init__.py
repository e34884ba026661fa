"""The built-in manoeuvres, one module each; importing this package registers them all.

Every module in this folder is imported (in name order) and registers itself with
:func:`trikedyn.manoeuvres.registry.register`: a new built-in test is one new file here.
"""

import importlib
import pkgutil

for _info in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
    importlib.import_module(f"{__name__}.{_info.name}")
