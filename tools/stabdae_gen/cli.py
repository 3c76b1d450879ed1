# SPDX-License-Identifier: GPL-3.0-or-later
"""mbsgen MODEL.py --out DIR: runs MODEL.py's mechanism(), writes DIR/name.h and DIR/name.c.

Every refusal is one line on stderr, `mbsgen: ...`, and exit status 2, with nothing written:
both files are generated in memory first, then each written to a temporary file in DIR and
renamed over its name, so a file in DIR is either the old one or the new one, whole.

Whatever the model file raises is its failure, said in one line with exit status 2: every
BaseException, KeyboardInterrupt among them, since a model may raise one itself. Only the
user's own Ctrl-C (SIGINT, told apart by a handler of our own while the model runs) is an
interruption: `mbsgen: interrupted`, exit status 130 (128 + SIGINT, as a shell says it)."""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import os
import runpy
import signal
import sys
import tempfile
import threading
import warnings
from collections.abc import Iterator, Sequence
from types import FrameType
from typing import NoReturn

from . import __version__
from .cwriter import header, source
from .errors import ModelError
from .mechanism import Mechanism

ARGUMENTS = "MODEL.py --out DIR [--name NAME]"


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:
        raise ModelError(f"{message} (usage: {self.usage})")


def _parse(argv: Sequence[str], prog: str) -> argparse.Namespace:
    parser = _Parser(
        prog=prog,
        usage=f"{prog} {ARGUMENTS}",
        description=(
            "Writes DIR/name.h and DIR/name.c, a mechanism of <stabdae/mbs.h> with exact "
            "derivatives, from MODEL.py's mechanism() (a stabdae_gen.Mechanism)."
        ),
    )
    parser.add_argument("model", metavar="MODEL.py", help="the description")
    parser.add_argument(
        "--out",
        metavar="DIR",
        required=True,
        help="where to write name.h and name.c (created if missing)",
    )
    parser.add_argument(
        "--name", help="refuse a mechanism of another name (the build expects NAME.h and NAME.c)"
    )
    return parser.parse_args(argv)


class Interrupted(KeyboardInterrupt):
    """The user's Ctrl-C while the model ran, told apart from a KeyboardInterrupt that the model
    raises itself (which is the model's failure)."""


def _raise_interrupted(signum: int, frame: FrameType | None) -> NoReturn:
    raise Interrupted()


@contextlib.contextmanager
def _user_interrupts() -> Iterator[None]:
    """SIGINT raises Interrupted while the block runs, where Python would raise a plain
    KeyboardInterrupt (in the main thread only: Python delivers signals there alone)."""
    ours = (
        threading.current_thread() is threading.main_thread()
        and signal.getsignal(signal.SIGINT) is signal.default_int_handler
    )
    if ours:
        signal.signal(signal.SIGINT, _raise_interrupted)
    try:
        yield
    finally:
        if ours:
            signal.signal(signal.SIGINT, signal.default_int_handler)


def _said(err: BaseException) -> str:
    """`Type: message` of an exception the model raised; the message is the model's code too
    (its __str__ may fail)."""
    try:
        message = str(err)
    except Exception:  # any failure of the model's own __str__
        message = "(its message cannot be printed)"
    return f"{type(err).__name__}: {message}" if message else type(err).__name__


def _model_file(path: str) -> None:
    if not os.path.exists(path):
        raise ModelError(f"{path}: no such file")
    if not os.path.isfile(path):
        raise ModelError(f"{path}: not a file")


def load(path: str) -> Mechanism:
    """The Mechanism of the model file's mechanism()."""
    _model_file(path)
    # the model's folder on the path while it runs, as for a script: it may import a helper
    # module beside it
    folder = os.path.dirname(os.path.abspath(path))
    sys.path.insert(0, folder)
    try:
        with _user_interrupts():
            return _run(path)
    finally:
        sys.path.remove(folder)


def _run(path: str) -> Mechanism:
    try:
        with warnings.catch_warnings():  # sympy's deprecations would break the one line
            warnings.simplefilter("ignore")
            return _mechanism(path)
    except (ModelError, Interrupted):
        raise
    except SystemExit as err:
        raise ModelError(f"{path}: exited ({err.code}) before giving a mechanism") from None
    except BaseException as err:  # the model file's own error, said in one line
        raise ModelError(f"{path}: {_said(err)}") from None


def _mechanism(path: str) -> Mechanism:
    scope = runpy.run_path(path, run_name="stabdae_gen_model")
    make = scope.get("mechanism")
    if not callable(make):
        raise ModelError(f"{path} defines no function mechanism()")
    try:
        mech = make()
    except (ModelError, SystemExit, Interrupted):
        raise
    except BaseException as err:
        raise ModelError(f"{path}: mechanism(): {_said(err)}") from None
    if not isinstance(mech, Mechanism):
        raise ModelError(
            f"{path}: mechanism() returned a {type(mech).__name__}, not a stabdae_gen.Mechanism"
        )
    return mech


def banner(digest: str, path: str, filename: str) -> str:
    return (
        f"/* {filename}: generated by stabdae_gen {__version__} (tools/mbsgen) from "
        f"{os.path.basename(path)},\n * sha256 {digest}.\n"
        " * Do not edit: change the model and generate again. */\n"
    )


def generate(path: str) -> tuple[Mechanism, dict[str, str]]:
    """The model file's mechanism and its files, {filename: text}."""
    _model_file(path)
    # the digest of the file as it is run (read before it runs: a file changed or removed
    # meanwhile is not what the banner names)
    try:
        with open(path, "rb") as f:
            digest = hashlib.sha256(f.read()).hexdigest()
    except OSError as err:
        raise ModelError(f"{path}: {err.strerror or err}") from None
    mech = load(path)
    h, c = f"{mech.name}.h", f"{mech.name}.c"
    return mech, {
        h: header(mech, banner(digest, path, h)),
        c: source(mech, banner(digest, path, c)),
    }


def one_line(text: object) -> str:
    """text as one line: a message from the model or from sympy may hold newlines (or other
    characters that are not printable, which a terminal would act on)."""
    text = " ".join(part.strip() for part in str(text).splitlines() if part.strip())
    return "".join(ch if ch.isprintable() else " " for ch in text)


def write(out: str, files: dict[str, str]) -> None:
    """Each file to a temporary one in out, then renamed over its name."""
    if os.path.exists(out) and not os.path.isdir(out):
        raise ModelError(f"--out {out}: not a directory")
    staged, created = [], not os.path.exists(out)
    # mkstemp makes its file readable by its owner alone: the files get the mode a new file
    # gets (0666 less the umask), as a compiler's output does, for an install or another user
    umask = os.umask(0)
    os.umask(umask)
    try:
        os.makedirs(out, exist_ok=True)
        for name, text in files.items():
            fd, tmp = tempfile.mkstemp(prefix=f".{name}.", dir=out)
            with os.fdopen(fd, "w") as f:
                f.write(text)
            os.chmod(tmp, 0o666 & ~umask)
            staged.append((tmp, os.path.join(out, name)))
        for tmp, final in staged:
            os.replace(tmp, final)
    except OSError as err:
        for tmp, _ in staged:
            if os.path.exists(tmp):
                os.remove(tmp)
        if created and os.path.isdir(out) and not os.listdir(out):
            os.rmdir(out)
        raise ModelError(f"--out {out}: {err.strerror or err}") from None


def run() -> NoReturn:
    """The command stabdae-gen (pyproject.toml's entry point): main on the command line, its
    messages under that name."""
    sys.exit(main(sys.argv[1:], prog="stabdae-gen"))


def main(argv: Sequence[str], prog: str = "mbsgen") -> int:
    """The generator's command: prog names it in its messages (tools/mbsgen and python -m
    stabdae_gen are mbsgen, the installed command stabdae-gen)."""
    try:
        args = _parse(argv, prog)
        mech, files = generate(args.model)
        if args.name is not None and mech.name != args.name:
            raise ModelError(f"{args.model} names its mechanism {mech.name!r}, not {args.name!r}")
        write(args.out, files)
    except ModelError as err:
        print(f"{prog}: {one_line(err)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # the user's Ctrl-C (a model's own is a ModelError above)
        print(f"{prog}: interrupted", file=sys.stderr)
        return 130
    n_c = len(mech.c)
    print(
        f"{prog}: {mech.name}: {mech.n} coordinates, {n_c} constraint{'s' * (n_c != 1)} -> "
        + ", ".join(os.path.join(args.out, name) for name in files)
    )
    return 0
