"""`extends` in a vehicle file: a preset, or a .toml file in the including file's folder or below it.

Each refusal is an InputError of one line naming the including file, and never shows the target's content
or its keys (the "secret" file below has a key that must not appear in any message).
"""

import os
import time

import pytest

from trikedyn.errors import InputError, ParameterError
from trikedyn.params import load_vehicle, parse_vehicle
from trikedyn.params.extends import MAX_EXTENDS
from trikedyn.params.tomlfile import MAX_FILE_BYTES

SECRET_KEY = "api_token_9f8e7d"


@pytest.fixture
def layout(tmp_path):
    """tmp/outside/secret.toml (valid TOML with a secret key), tmp/work/ (the user's folder)."""
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "secret.toml").write_text(f'{SECRET_KEY} = "s3cr3t-value"\n[mass]\ncurb_kg = 1\n', encoding="utf-8")
    work = tmp_path / "work"
    (work / "sub").mkdir(parents=True)
    return tmp_path, work


def _refused(file, *needles):
    with pytest.raises(ParameterError) as info:
        load_vehicle(file)
    message = str(info.value)
    assert "\n" not in message and message.startswith(str(file))
    assert SECRET_KEY not in message and "s3cr3t" not in message
    for needle in needles:
        assert needle in message, message
    return message


def _vehicle(folder, extends, name="v.toml"):
    file = folder / name
    file.write_text(f'extends = "{extends}"\nname = "mine"\n', encoding="utf-8")
    return file


def test_extends_a_file_in_the_same_folder_or_below(layout):
    _, work = layout
    (work / "sub" / "base.toml").write_text('extends = "reference-etrike"\n[mass]\ndriver_kg = 95.0\n')
    (work / "sub" / "deeper").mkdir()
    (work / "sub" / "deeper" / "leaf.toml").write_text('extends = "reference-etrike"\n[mass]\ndriver_kg = 60.0\n')
    p = load_vehicle(_vehicle(work, "sub/base.toml")).params
    assert p.name == "mine" and p.mass.driver_kg == 95.0 and p.mass.curb_kg == 508.0
    # relative to the including file's own folder, below it
    (work / "sub" / "mid.toml").write_text('extends = "deeper/leaf.toml"\n')
    assert load_vehicle(_vehicle(work, "sub/mid.toml")).params.mass.driver_kg == 60.0


@pytest.mark.parametrize(
    ("extends", "needle"),
    [
        ("{outside}/secret.toml", "absolute path"),
        ("/etc/passwd", "absolute path"),
        ("/proc/self/environ", "absolute path"),
        ("../outside/secret.toml", "'..'"),
        ("sub/../../outside/secret.toml", "'..'"),
        ("~/secret.toml", "absolute path"),
    ],
)
def test_extends_out_of_the_folder_is_refused_unread(layout, extends, needle):
    root, work = layout
    _refused(_vehicle(work, extends.format(outside=root / "outside")), "extends:", needle)


def test_extends_through_a_symbolic_link_out_of_the_folder_is_refused(layout):
    root, work = layout
    os.symlink(root / "outside" / "secret.toml", work / "link.toml")
    os.symlink(root / "outside", work / "sub" / "door")
    _refused(_vehicle(work, "link.toml"), "leads out of this file's folder")
    _refused(_vehicle(work, "sub/door/secret.toml"), "leads out of this file's folder")
    # a link that stays inside is fine
    (work / "sub" / "base.toml").write_text('extends = "reference-etrike"\n')
    os.symlink(work / "sub" / "base.toml", work / "inside.toml")
    assert load_vehicle(_vehicle(work, "inside.toml")).params.name == "mine"


def test_extends_a_missing_file_or_an_unknown_preset(layout):
    _, work = layout
    _refused(_vehicle(work, "nothere.toml"), "no preset or file 'nothere.toml'")
    _refused(_vehicle(work, "reference-etrik"), "did you mean 'reference-etrike'")
    (work / "v.toml").write_text("extends = 3\n")
    _refused(work / "v.toml", "expected a preset name or a .toml file")


def test_extends_name_too_long_or_with_control_characters(layout):
    _, work = layout
    _refused(_vehicle(work, "x" * 5000 + ".toml"), "too long")
    (work / "v.toml").write_text('extends = "a\\u0000b.toml"\n')
    _refused(work / "v.toml", "control character")


def test_extended_file_not_utf8_or_too_large(layout):
    _, work = layout
    (work / "latin.toml").write_bytes(b'name = "caf\xe9"\n')
    with pytest.raises(ParameterError, match=r"latin\.toml: not UTF-8 text \(invalid continuation byte at byte 11\)"):
        load_vehicle(_vehicle(work, "latin.toml"))
    (work / "big.toml").write_bytes(b"#" * (MAX_FILE_BYTES + 1) + b"\n")
    with pytest.raises(ParameterError, match=r"big\.toml: larger than 1024 KiB"):
        load_vehicle(_vehicle(work, "big.toml"))
    with pytest.raises(ParameterError, match=r"big\.toml: larger than 1024 KiB"):
        load_vehicle(work / "big.toml")  # the file given itself, too


def test_extends_a_pipe_does_not_wait(layout):
    _, work = layout
    os.mkfifo(work / "pipe.toml")
    start = time.perf_counter()
    _refused(_vehicle(work, "pipe.toml"), "no preset or file 'pipe.toml'")
    with pytest.raises(ParameterError):
        load_vehicle(work / "pipe.toml")
    assert time.perf_counter() - start < 5.0


def test_extends_chain_depth_and_cycles(tmp_path):
    # v.toml -> c0 -> c1 -> ... : MAX_EXTENDS links are fine, one more is refused
    def chain(n):
        for i in range(n):
            target = f"c{i + 1}.toml" if i < n - 1 else "reference-etrike"
            (tmp_path / f"c{i}.toml").write_text(f'extends = "{target}"\n')
        return _vehicle(tmp_path, "c0.toml")

    assert load_vehicle(chain(MAX_EXTENDS - 1)).params.name == "mine"  # v + 7 files + the preset: 8 links
    with pytest.raises(ParameterError, match=f"more than {MAX_EXTENDS} in a chain"):
        load_vehicle(chain(MAX_EXTENDS))
    (tmp_path / "a.toml").write_text('extends = "b.toml"\n')
    (tmp_path / "b.toml").write_text('extends = "a.toml"\n')
    with pytest.raises(ParameterError, match=r"a cycle \(a\.toml -> b\.toml -> a\.toml\)"):
        load_vehicle(tmp_path / "a.toml")
    (tmp_path / "self.toml").write_text('extends = "self.toml"\n')
    with pytest.raises(ParameterError, match=r"a cycle \(self\.toml -> self\.toml\)"):
        load_vehicle(tmp_path / "self.toml")


def test_parse_vehicle_text_extends_relative_to_its_origin(tmp_path):
    (tmp_path / "base.toml").write_text('extends = "reference-etrike"\n[mass]\ndriver_kg = 80.0\n')
    pset = parse_vehicle('extends = "base.toml"\nname = "t"\n', origin=str(tmp_path / "mine.toml"))
    assert pset.params.mass.driver_kg == 80.0
    with pytest.raises(ParameterError, match="'..'"):
        parse_vehicle('extends = "../base.toml"\n', origin=str(tmp_path / "sub" / "mine.toml"))


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("a = " + "[" * 2000 + "]" * 2000, "nested more than"),
        ("[" + ".".join(["t"] * 5000) + "]\n", "nested more than"),
        ("a = " + "9" * 5000, "a number too long"),
        ("curb = 99999999999999999999999\n", "curb: integer beyond 64 bits"),
        ('name = "' + "x" * 20_000 + '"\n', "name: a text of 20000 characters"),
        ('extends = "reference-etrike"\n[[wheels]]\nname = [1]\n', "input should be a valid string"),
        ('extends = "reference-etrike"\n[[wheels]]\nname = {a = 1}\n', "input should be a valid string"),
    ],
)
def test_hostile_toml_gives_one_line(tmp_path, text, needle):
    """Each once escaped as RecursionError, ValueError or TypeError, or made a line of megabytes."""
    file = tmp_path / "v.toml"
    file.write_text(text, encoding="utf-8")
    with pytest.raises(InputError) as info:
        load_vehicle(file)
    assert needle in str(info.value) and "\n" not in str(info.value) and len(str(info.value)) < 400


def test_top_level_name_too_long_is_an_input_error(tmp_path):
    with pytest.raises(ParameterError, match="no such parameter file"):
        load_vehicle(str(tmp_path / ("y" * 5000)) + ".toml")
    with pytest.raises(ParameterError, match="unknown vehicle"):
        load_vehicle("z" * 5000)


def test_a_layout_change_through_extends_is_said_in_words():
    """Issue 20: a delta extended into a tadpole said 'wheels: tuple should have at most 3 items'."""
    wheel = 'radius_m = 0.27\nmass_kg = 12.0\nspin_inertia_kgm2 = 0.2\nsuspension = "front"\n'
    text = ('extends = "reference-etrike"\nname = "t"\n'
            + "".join(f'[[wheels]]\nname = "{n}"\nx_m = 1.95\ny_m = {y}\n{wheel}' for n, y in
                      (("front_left", 0.55), ("front_right", -0.55))))
    with pytest.raises(ParameterError, match=r"adds the wheels front_left, front_right: a file that extends"):
        parse_vehicle(text, "t.toml")
    with pytest.raises(ParameterError, match=r"changes the layout from delta to tadpole.*extend 'reference-tadpole'"):
        parse_vehicle('extends = "reference-etrike"\nlayout = "tadpole"\n', "t.toml")
    assert parse_vehicle('extends = "reference-tadpole"\nname = "t"\n', "t.toml").params.layout == "tadpole"
