"""Plug-ins used by ``tests/test_registry.py``: each extension is one module that registers itself on import."""
