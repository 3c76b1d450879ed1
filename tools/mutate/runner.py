# SPDX-License-Identifier: GPL-3.0-or-later
"""Running the mutants: a private copy of the source tree (build/mutate/src-tree) and a build
dir of its own (build/mutate/build). The working tree is only read, once, at the start; each
mutant rewrites one file of the copy, rebuilds incrementally and runs the tests until the first
failure, then the file is restored."""

import json
import os
import re
import shutil
import signal
import subprocess
import threading
import time
from dataclasses import dataclass, field

CMAKE_OPTIONS = [
    "-DSTABDAE_BUILD_TOOLS=OFF",
    "-DCMAKE_BUILD_TYPE=RelWithDebInfo",
    "-DSTABDAE_WERROR=OFF",
]


def python_option(root):
    """The harness's venv (build/venv, made by tools/check) as the build's Python, so that the
    unit tests written in Python (the tableaus' order conditions) run in the campaign too."""
    python = os.path.join(root, "build", "venv", "bin", "python")
    return [f"-DPython3_EXECUTABLE={python}"] if os.path.exists(python) else []


def source_files(root):
    """The working tree's files (tracked and untracked, not ignored), relative to root."""
    try:
        out = subprocess.run(
            ["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
            cwd=root,
            capture_output=True,
            check=True,
        ).stdout
        files = [f for f in out.decode().split("\0") if f]
    except (OSError, subprocess.CalledProcessError):
        files = []
        for d, dirs, names in os.walk(root):
            dirs[:] = [x for x in dirs if x not in (".git", "build")]
            files += [os.path.relpath(os.path.join(d, n), root) for n in names]
    return [f for f in files if os.path.isfile(os.path.join(root, f))]


def _same(a, b):
    try:
        if os.path.getsize(a) != os.path.getsize(b):
            return False
        with open(a, "rb") as fa, open(b, "rb") as fb:
            return fa.read() == fb.read()
    except OSError:
        return False


def sync_tree(root, tree):
    """Makes tree a copy of root's files; unchanged files keep their time stamps, so the
    build dir stays incremental across runs."""
    files = set(source_files(root))
    for f in files:
        src, dst = os.path.join(root, f), os.path.join(tree, f)
        if not _same(src, dst):
            os.makedirs(os.path.dirname(dst), exist_ok=True)
            shutil.copy2(src, dst)
    for d, _, names in os.walk(tree):
        for n in names:
            path = os.path.join(d, n)
            if os.path.relpath(path, tree) not in files:
                os.remove(path)


def _descendants(pid):
    """The processes below pid, from /proc: Check runs each test case in a forked child that
    moves to a process group of its own, out of reach of the group kill."""
    children = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as f:
                    ppid = int(f.read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
            children.setdefault(ppid, []).append(int(entry))
    out, todo = [], [pid]
    while todo:
        for c in children.get(todo.pop(), []):
            out.append(c)
            todo.append(c)
    return out


def _kill_group(proc):
    """Kills proc, its process group and every process below it (before their parent dies and
    they are re-parented out of sight)."""
    for pid in _descendants(proc.pid) if os.path.isdir("/proc") else []:
        for kill in (os.kill, os.killpg):
            try:
                kill(pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


_LIVE = set()  # the processes under way, for kill_all
_LIVE_LOCK = threading.Lock()


def kill_all():
    """Kills every process group still running (the tests of the worker threads on Ctrl-C)."""
    with _LIVE_LOCK:
        procs = list(_LIVE)
    for p in procs:
        _kill_group(p)


def run_quiet(cmd, cwd=None, timeout=None, env=None, log=None, output=True):
    """Runs cmd in its own process group (killed whole on timeout or Ctrl-C); returns
    (exit status or None on timeout, output). Without output, nothing is read from the
    process: no stray descendant can then hold a pipe open and block the wait."""
    sink = subprocess.PIPE if output else subprocess.DEVNULL
    proc = subprocess.Popen(
        cmd, cwd=cwd, env=env, stdout=sink, stderr=subprocess.STDOUT, start_new_session=True
    )
    with _LIVE_LOCK:
        _LIVE.add(proc)
    try:
        out, _ = proc.communicate(timeout=timeout)
        rc = proc.returncode
    except subprocess.TimeoutExpired:
        _kill_group(proc)
        out, _ = proc.communicate()
        rc = None
    except BaseException:
        _kill_group(proc)
        proc.wait()
        raise
    finally:
        with _LIVE_LOCK:
            _LIVE.discard(proc)
    text = (out or b"").decode(errors="replace")
    if log:
        with open(log, "w") as f:
            f.write(text)
    return rc, text


@dataclass
class Test:
    name: str
    command: list
    cwd: str
    env: dict
    will_fail: bool = False
    baseline: float = 0.0  # seconds on the unmutated build


def load_tests(build, labels):
    """The ctest tests carrying one of labels, from ctest's own JSON description."""
    _, out = run_quiet(["ctest", "--show-only=json-v1"], cwd=build)
    tests = []
    for t in json.loads(out[out.index("{") :])["tests"]:
        props = {p["name"]: p["value"] for p in t.get("properties", [])}
        if not set(props.get("LABELS", [])) & set(labels) or props.get("DISABLED"):
            continue
        env = dict(os.environ)
        env.update(dict(kv.split("=", 1) for kv in props.get("ENVIRONMENT", [])))
        tests.append(
            Test(
                t["name"],
                t["command"],
                props.get("WORKING_DIRECTORY", build),
                env,
                bool(props.get("WILL_FAIL")),
            )
        )
    return tests


class TestRunner:
    """Runs tests in a given order on `jobs` workers and stops at the first failure."""

    def __init__(self, jobs, timeout_floor, timeout_factor):
        self.jobs = max(1, jobs)
        self.floor, self.factor = timeout_floor, timeout_factor

    def timeout(self, test):
        return max(self.floor, self.factor * test.baseline)

    def run_one(self, test):
        """(passed, timed_out, seconds)."""
        t0 = time.monotonic()
        rc, _ = run_quiet(
            test.command, cwd=test.cwd, env=test.env, timeout=self.timeout(test), output=False
        )
        secs = time.monotonic() - t0
        if rc is None:
            return False, True, secs
        return (rc != 0) == test.will_fail, False, secs

    def run(self, tests, stop_on_failure=True):
        """Returns (first failing test or None, timed out?, {name: seconds})."""
        queue, lock = list(tests), threading.Lock()
        result = {"failed": None, "timeout": False, "times": {}}
        stop = threading.Event()

        def worker():
            while not stop.is_set():
                with lock:
                    if not queue:
                        return
                    test = queue.pop(0)
                ok, timed_out, secs = self.run_one(test)
                with lock:
                    result["times"][test.name] = secs
                    if not ok and result["failed"] is None:
                        result["failed"], result["timeout"] = test, timed_out
                        if stop_on_failure:
                            stop.set()

        threads = [threading.Thread(target=worker, daemon=True) for _ in range(self.jobs)]
        for th in threads:
            th.start()
        for th in threads:
            while th.is_alive():
                th.join(0.2)  # short joins: Ctrl-C reaches the main thread
        return result["failed"], result["timeout"], result["times"]


@dataclass
class Outcome:
    verdict: str  # killed, survived, timeout, invalid, same-object
    seconds: float
    killer: str = ""  # the first failing test
    build_seconds: float = 0.0
    tests_run: int = 0
    detail: str = ""


@dataclass
class Workspace:
    root: str
    work: str
    jobs: int = 2
    labels: tuple = ("unit", "examples")
    sanitize: bool = False  # built with AddressSanitizer (the carve operator's mutants)
    timeout_floor: float = 10.0
    timeout_factor: float = 10.0
    tests: list = field(default_factory=list)
    history: dict = field(default_factory=dict)  # file -> test names that killed, newest first
    original_objects: dict = field(default_factory=dict)  # file -> its unmutated object

    @property
    def tree(self):
        return os.path.join(self.work, "src-tree")

    @property
    def build(self):
        return os.path.join(self.work, "build-asan" if self.sanitize else "build")

    def prepare(self, say):
        """Copies the sources, configures if needed, builds and runs the baseline."""
        os.makedirs(self.work, exist_ok=True)
        sync_tree(self.root, self.tree)
        if self._configured_elsewhere():
            shutil.rmtree(self.build)  # a build dir of another checkout: start afresh
        if not os.path.exists(os.path.join(self.build, "CMakeCache.txt")):
            say(f"configuring {os.path.relpath(self.build, self.root)}")
            gen = ["-G", "Ninja"] if shutil.which("ninja") else []
            rc, out = run_quiet(
                ["cmake", "-S", self.tree, "-B", self.build]
                + gen
                + CMAKE_OPTIONS
                + python_option(self.root)
                + (["-DSTABDAE_SANITIZE=ON"] if self.sanitize else []),
                log=os.path.join(self.work, "configure.log"),
            )
            if rc != 0:
                raise SystemExit(f"mutate: cmake configure failed, see {self.work}/configure.log")
        t0 = time.monotonic()
        if self.compile() != 0:
            raise SystemExit(
                f"mutate: the unmutated tree does not build, see {self.work}/build.log"
            )
        say(f"built in {time.monotonic() - t0:.1f} s")
        self.original_objects = {}
        for f in source_files(self.root):
            if f.startswith("src/") and f.endswith(".c"):
                self.original_objects[f] = _read(self.object_file(f))
        self.tests = load_tests(self.build, self.labels)
        self.load_history()
        return self.baseline(say)

    def _configured_elsewhere(self):
        """Whether the build dir's cache names a source dir other than this copy."""
        try:
            with open(os.path.join(self.build, "CMakeCache.txt")) as f:
                for line in f:
                    if line.startswith("CMAKE_HOME_DIRECTORY:"):
                        home = line.split("=", 1)[1].strip()
                        return os.path.realpath(home) != os.path.realpath(self.tree)
        except OSError:
            pass
        return False

    def compile(self):
        rc, _ = run_quiet(
            ["cmake", "--build", self.build, "-j", str(self.jobs)],
            timeout=600,
            log=os.path.join(self.work, "build.log"),
        )
        return rc

    def baseline(self, say):
        """Runs every test once unmutated: their times set the timeouts and the order; a test
        that already fails is left out (and reported)."""
        runner = TestRunner(self.jobs, 60.0, 1.0)
        t0 = time.monotonic()
        broken = []
        for test in self.tests:
            ok, _, secs = runner.run_one(test)
            test.baseline = secs
            if not ok:
                broken.append(test.name)
        self.tests = [t for t in self.tests if t.name not in broken]
        say(
            f"baseline: {len(self.tests)} tests pass ({time.monotonic() - t0:.1f} s serial)"
            + (f"; left out, failing unmutated: {', '.join(broken)}" if broken else "")
        )
        return broken

    def order(self, relfile):
        """Tests for a mutant of relfile: those that killed its earlier mutants, then those
        whose name shares a word with the file's, then the rest, each group fastest first."""
        stem = os.path.splitext(os.path.basename(relfile))[0].lower()
        words = [w for w in stem.split("_") if len(w) > 1]
        killers = self.history.get(relfile, [])
        by_name = {t.name: t for t in self.tests}
        first = [by_name[n] for n in killers if n in by_name]

        def related(test):  # whole words of the name: "maps" for map_dgrad, not "evaluations"
            names = re.split(r"[^a-z0-9]+", test.name.lower())
            return any(n.startswith(w) for n in names for w in words)

        rest = sorted(
            (t for t in self.tests if t.name not in killers),
            key=lambda t: (not related(t), t.baseline),
        )
        return first + rest

    @property
    def history_file(self):
        return os.path.join(self.work, "killers.json")

    def load_history(self):
        """The tests that killed each file's mutants in earlier runs: they go first again."""
        try:
            with open(self.history_file) as f:
                self.history = json.load(f)
        except (OSError, ValueError):
            self.history = {}

    def save_history(self):
        with open(self.history_file, "w") as f:
            json.dump(self.history, f, indent=1)

    def object_file(self, relfile):
        """The object of src/<path>.c: CMake writes it to stabdae_obj.dir/<path>.c.o, so the path
        below src/ (not the name alone) tells apart files of the same name in two folders."""
        below_src = os.path.relpath(relfile, "src") + ".o"
        for d, _, _ in os.walk(self.build):
            if os.path.basename(d) == "stabdae_obj.dir":
                path = os.path.join(d, below_src)
                return path if os.path.isfile(path) else None
        return None

    def run_mutant(self, mutant, original_text):
        """Applies, builds, tests and restores one mutant."""
        path = os.path.join(self.tree, mutant.file)
        t0 = time.monotonic()
        obj = self.object_file(mutant.file)
        before = self.original_objects.get(mutant.file)
        try:
            _write(path, mutant.apply(original_text))
            rc = self.compile()
            build_secs = time.monotonic() - t0
            if rc != 0:
                return Outcome(
                    "invalid",
                    time.monotonic() - t0,
                    build_seconds=build_secs,
                    detail="does not compile",
                )
            if before is not None and _read(obj) == before:
                return Outcome(
                    "same-object",
                    time.monotonic() - t0,
                    build_seconds=build_secs,
                    detail="the compiled object is identical to the original's",
                )
            runner = TestRunner(self.jobs, self.timeout_floor, self.timeout_factor)
            failed, timed_out, times = runner.run(self.order(mutant.file))
        finally:
            _write(path, original_text)
        secs = time.monotonic() - t0
        if failed is None:
            return Outcome("survived", secs, build_seconds=build_secs, tests_run=len(times))
        hist = self.history.setdefault(mutant.file, [])
        if failed.name in hist:
            hist.remove(failed.name)
        hist.insert(0, failed.name)
        return Outcome(
            "timeout" if timed_out else "killed", secs, failed.name, build_secs, len(times)
        )

    def restore_build(self):
        """Rebuilds the unmutated copy, so that the next run starts from it, and keeps the
        order of the killing tests for it."""
        self.compile()
        self.save_history()


def _read(path):
    if not path:
        return None
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError:
        return None


def _write(path, text):
    with open(path, "w") as f:
        f.write(text)
