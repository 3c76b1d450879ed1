# SPDX-License-Identifier: GPL-3.0-or-later
"""The generator as a Python user installs it: `pip install tools/stabdae_gen` (pyproject.toml)
gives the command stabdae-gen, which writes the same files as `python -m stabdae_gen`, and the
module, whose version is the project's. Installed with pip into a folder of its own (no
dependencies fetched: the harness's venv has sympy, setuptools and wheel), from a copy of the
folder, since setuptools writes its build/ and egg-info beside the sources."""

import os
import shutil
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
PACKAGE = os.path.dirname(HERE)
MODEL = os.path.join(PACKAGE, "..", "..", "examples", "generator", "cart_pendulum.py")


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    target, source = tmp_path_factory.mktemp("site"), tmp_path_factory.mktemp("source")
    copy = shutil.copytree(
        PACKAGE, source / "stabdae_gen", ignore=shutil.ignore_patterns("__pycache__")
    )
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "install",
            "-q",
            "--no-deps",
            "--no-build-isolation",
            "--target",
            str(target),
            str(copy),
        ],
        check=True,
        capture_output=True,
    )
    return target


def run(cmd, target, cwd):
    env = dict(os.environ, PYTHONPATH=str(target))
    return subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True)


def test_the_command_writes_what_the_module_writes(installed, tmp_path):
    command = os.path.join(str(installed), "bin", "stabdae-gen")
    by_command = run([command, MODEL, "--out", str(tmp_path / "a")], installed, tmp_path)
    by_module = run(
        [sys.executable, "-m", "stabdae_gen", MODEL, "--out", str(tmp_path / "b")],
        installed,
        tmp_path,
    )
    assert by_command.returncode == 0, by_command.stderr
    assert by_module.returncode == 0, by_module.stderr
    for name in ("cart_pendulum.h", "cart_pendulum.c"):
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()


def test_a_refusal_is_one_line_and_status_2(installed, tmp_path):
    command = os.path.join(str(installed), "bin", "stabdae-gen")
    out = run([command, "no_such_model.py", "--out", str(tmp_path)], installed, tmp_path)
    assert out.returncode == 2
    assert len(out.stderr.strip().splitlines()) == 1
    assert out.stderr.startswith("stabdae-gen: ")  # under the command's own name


def test_the_installed_module_is_the_package_alone(installed):
    names = sorted(os.listdir(os.path.join(str(installed), "stabdae_gen")))
    assert "tests" not in names and "cli.py" in names and "pyproject.toml" not in names


def test_the_installed_package_carries_its_type_hints(installed):
    # PEP 561: without py.typed a user's mypy ignores the package's hints
    assert os.path.isfile(os.path.join(str(installed), "stabdae_gen", "py.typed"))
