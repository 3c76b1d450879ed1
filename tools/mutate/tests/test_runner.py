# SPDX-License-Identifier: GPL-3.0-or-later
"""The runner's pieces that decide what runs: the sample's spread over the files, the tests'
order for a mutant, the copy of the tree and the build's Python."""

import os

from mutate.main import spread
from mutate.operators import Mutant
from mutate.runner import Test as CtestTest
from mutate.runner import Workspace, python_option, sync_tree


def mutant(file, key, start=0):
    return Mutant(file, "rel", key, 0, 1, start, start + 1, "<=", "a < b", "a <= b")


def test_the_sample_spreads_over_the_files_and_depends_on_the_ids_alone():
    many = [mutant("src/a.c", f"{i:08x}", i) for i in range(30)]
    few = [mutant("src/b.c", f"{i:08x}", i) for i in range(3)]
    chosen = spread(many + few, 6)
    assert len(chosen) == 6
    assert {m.file for m in chosen} == {"src/a.c", "src/b.c"}
    again = spread(list(reversed(few)) + list(reversed(many)), 6)
    assert sorted(m.id for m in again) == sorted(m.id for m in chosen)
    assert spread(few, 10) == few  # k beyond the count: every one


def test_the_tests_that_killed_before_run_first_then_the_related_fastest_first(tmp_path):
    ws = Workspace(str(tmp_path), str(tmp_path / "work"))
    names = ("maps.slow", "other.fast", "maps.fast", "errors.killer")
    ws.tests = [CtestTest(name, [], "", {}, False) for name in names]
    for t, secs in zip(ws.tests, (2.0, 0.1, 0.5, 9.0)):
        t.baseline = secs
    ws.history = {"src/maps/map_dgrad.c": ["errors.killer"]}
    order = [t.name for t in ws.order("src/maps/map_dgrad.c")]
    assert order == ["errors.killer", "maps.fast", "maps.slow", "other.fast"]


def test_the_copy_follows_the_tree_and_drops_what_left_it(tmp_path):
    root, tree = tmp_path / "root", tmp_path / "tree"
    (root / "src").mkdir(parents=True)
    (root / "src" / "a.c").write_text("int a;\n")
    (tree / "src").mkdir(parents=True)
    (tree / "src" / "gone.c").write_text("int gone;\n")
    sync_tree(str(root), str(tree))
    assert (tree / "src" / "a.c").read_text() == "int a;\n"
    assert not (tree / "src" / "gone.c").exists()


def test_the_build_takes_the_harness_python_when_there_is_one(tmp_path):
    assert python_option(str(tmp_path)) == []
    venv = tmp_path / "build" / "venv" / "bin"
    venv.mkdir(parents=True)
    (venv / "python").write_text("")
    assert python_option(str(tmp_path)) == [
        "-DPython3_EXECUTABLE=" + os.path.join(str(tmp_path), "build", "venv", "bin", "python")
    ]


def test_a_sanitized_campaign_builds_apart(tmp_path):
    plain = Workspace(str(tmp_path), str(tmp_path / "work"))
    asan = Workspace(str(tmp_path), str(tmp_path / "work"), sanitize=True)
    assert plain.build != asan.build and asan.build.endswith("build-asan")
