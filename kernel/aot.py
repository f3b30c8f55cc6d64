"""Loading numba kernels compiled ahead of time (numba.pycc), for a front end's compiled
readers, with numba's JIT as the fallback.

A kernel source module (e.g. :mod:`stepnc.p21_kernels`) holds numba functions and their
signatures, and compiles them with numba.pycc (:func:`build_module`) when run as
``python -m MODULE DIR NAME``. :class:`Kernels` builds that extension module once, in a
child process (its compiler output never reaches ours), into the user's cache
(``$CNC_CACHE_DIR``, else ``$XDG_CACHE_HOME/cnc-toolchain``), under a name keyed by the
kernel source and the Python and numpy versions, and says so once on stderr. Loading the
built module takes under a millisecond and imports no numba. Where it cannot be built (no
C compiler, a cache directory that is not private), the same source runs through numba's
JIT; where numba is missing too, :meth:`Kernels.module` raises ImportError and the caller
takes its pure-Python path. The RS274/NGC fast lane and the Part 21 scanner load theirs so.
"""

from __future__ import annotations

import contextlib
import importlib
import importlib.util
import logging
import os
import stat
import subprocess
import sys
import sysconfig
import tempfile
import zlib
from pathlib import Path
from types import ModuleType
from typing import Any

#: warnings reach stderr through logging's last-resort handler when nobody configured one
_log = logging.getLogger("cnc.aot")


def cache_dir() -> Path:
    """``$CNC_CACHE_DIR`` when set, else ``$XDG_CACHE_HOME/cnc-toolchain`` (default
    ``~/.cache/cnc-toolchain``)."""
    own = os.environ.get("CNC_CACHE_DIR")
    if own:
        return Path(own)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "cnc-toolchain"


def private_dir(directory: Path) -> bool:
    """Make ``directory`` (mode 0700 when created) and say whether code may be loaded from
    it: it must be ours and writable by nobody else, or another user could plant a module."""
    try:
        directory.mkdir(mode=0o700, parents=True, exist_ok=True)
        st = directory.stat()
    except OSError:
        return False
    mine = not hasattr(os, "getuid") or st.st_uid == os.getuid()
    return mine and not st.st_mode & (stat.S_IWGRP | stat.S_IWOTH)


def build_module(directory: str, name: str, signatures: dict[str, tuple[Any, Any]]) -> None:
    """Compile a kernel source's ``signatures`` (exported name -> (numba function, numba
    signature)) ahead of time into extension module ``name`` in ``directory``; a kernel
    source runs this as its ``__main__`` (numba.pycc, imported only here)."""
    from numba.pycc import CC

    cc = CC(name)
    cc.output_dir = directory
    for exported, (function, signature) in signatures.items():
        cc.export(exported, signature)(function.py_func)
    cc.compile()


class Kernels:
    """The compiled kernels of one source module, loaded once per process.

    ``module`` is the kernel source's import name, ``prefix`` the stem of the built
    module's name, ``what`` how the one-off build is announced, ``jit_env`` an environment
    variable that, when set, skips the AOT module (the JIT path, for tests)."""

    def __init__(self, module: str, prefix: str, what: str, jit_env: str) -> None:
        self.module_name = module
        self.prefix = prefix
        self.what = what
        self.jit_env = jit_env
        spec = importlib.util.find_spec(module)
        assert spec is not None and spec.origin is not None, module
        self.source = Path(spec.origin)
        self._loaded: ModuleType | None = None

    def aot_name(self) -> str:
        """Module name of the AOT build of the current source for this Python and numpy
        (two 32-bit checksums: no OpenSSL to load at start-up)."""
        import numpy as np

        data = self.source.read_bytes() + (
            f"|{sys.version}|{np.__version__}|{sysconfig.get_platform()}".encode()
        )
        return f"{self.prefix}_{zlib.crc32(data):08x}{zlib.adler32(data):08x}"

    def build_aot(self, directory: Path, name: str) -> tuple[bool, str]:
        """Build module ``name`` into ``directory`` in a child process; the file appears
        atomically. Returns (ok, error text)."""
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        root = self.source
        for _ in self.module_name.split("."):
            root = root.parent
        env = dict(os.environ)
        env["PYTHONPATH"] = os.pathsep.join(p for p in (str(root), env.get("PYTHONPATH")) if p)
        if not private_dir(directory):
            return False, f"{directory}: not a private directory"
        try:
            with tempfile.TemporaryDirectory(dir=directory, prefix=".build-") as tmp:
                proc = subprocess.run(
                    [sys.executable, "-m", self.module_name, tmp, name],
                    capture_output=True,
                    env=env,
                    timeout=600,
                    stdin=subprocess.DEVNULL,
                )
                built = Path(tmp) / (name + suffix)
                if proc.returncode != 0 or not built.is_file():
                    return False, (proc.stderr or proc.stdout).decode(errors="replace")[-2000:]
                os.replace(built, directory / (name + suffix))
        except (OSError, subprocess.SubprocessError) as exc:
            return False, str(exc)
        return True, ""

    def load_aot(self, directory: Path) -> ModuleType | None:
        """The AOT module from ``directory``, built there first if missing; None when it
        cannot be built (the failure is remembered in ``NAME.failed``: delete it to retry)."""
        name = self.aot_name()
        path = directory / (name + sysconfig.get_config_var("EXT_SUFFIX"))
        failed = directory / (name + ".failed")
        if not private_dir(directory):
            _log.warning("not loading %s from %s: not a private directory", self.what, directory)
            return None
        if not path.is_file():
            if failed.exists():
                return None
            _log.warning("building %s, once, ~30 s (cached in %s)", self.what, directory)
            ok, error = self.build_aot(directory, name)
            if not ok:
                with contextlib.suppress(OSError):
                    failed.write_text(error)
                return None
        try:
            spec = importlib.util.spec_from_file_location(name, path)
            if spec is None or spec.loader is None:
                return None
            module = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(module)
        except ImportError:
            return None
        return module

    def load_jit(self) -> ModuleType:
        """The kernels through numba's JIT (imports numba; ImportError without it)."""
        return importlib.import_module(self.module_name)

    def module(self) -> ModuleType:
        """The module in use: AOT if possible, else JIT (loaded once per process).

        Raises ImportError when neither an AOT module nor numba is available."""
        if self._loaded is None:
            aot = None if os.environ.get(self.jit_env) else self.load_aot(cache_dir())
            self._loaded = aot if aot is not None else self.load_jit()
        return self._loaded

    def mode(self) -> str:
        """``"aot"`` or ``"jit"`` (loads the kernels if not yet; ImportError as
        :meth:`module`)."""
        return "jit" if self.module() is sys.modules.get(self.module_name) else "aot"
