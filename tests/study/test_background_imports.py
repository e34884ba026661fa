"""study.engine.background: the libraries a design needs after its evaluations, imported while they run."""

import sys

from trikedyn.study.engine.background import import_in_background


def test_the_modules_are_imported_in_a_daemon_thread_and_a_missing_one_is_left(tmp_path, monkeypatch):
    (tmp_path / "trikedyn_bg_probe.py").write_text("LOADED = True\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, "trikedyn_bg_probe", raising=False)
    thread = import_in_background("trikedyn_no_such_module_here", "trikedyn_bg_probe")
    assert thread.daemon
    thread.join(timeout=30)
    assert not thread.is_alive()
    assert sys.modules["trikedyn_bg_probe"].LOADED
    assert "trikedyn_no_such_module_here" not in sys.modules
