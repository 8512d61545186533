"""Kernels only linked (spurdyn.linking): their code reaches Python through the entries that
link it, computes what Numba's own build computes, raises what it raises, and a later
process that compiles another entry reads the linked kernels from the disk cache."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from spurdyn import linking

pytestmark = pytest.mark.skipif(not linking.AVAILABLE, reason="Numba's code library differs")

KERNELS = textwrap.dedent('''
    import numpy as np
    from spurdyn.jit import njit

    @njit
    def scaled(a, i):
        if i < 0:
            raise ValueError("negative index")
        return a[i] * 2.0

    @njit
    def total(a):
        s = 0.0
        for i in range(a.size):
            s += scaled(a, i) * np.sin(a[i])
        return s

    @njit(entry=True)
    def first(a, i):
        return total(a) + scaled(a, i)

    @njit(entry=True)
    def second(a):
        return total(a) * 3.0
''')

CHILD = textwrap.dedent('''
    import json, sys
    import numpy as np
    import kernels

    def linked_address(dispatcher):
        """Where the machine code of the kernel's own function is (0: none was emitted)."""
        overload = dispatcher.overloads[dispatcher.signatures[0]]
        return overload.library.get_pointer_to_function(overload.fndesc.llvm_func_name)
    a = np.linspace(0.1, 2.0, 7)
    out = {"entry": getattr(kernels, sys.argv[1])(*([a, 2] if sys.argv[1] == "first" else [a])),
           "python": (kernels.total.py_func(a) + kernels.scaled.py_func(a, 2)
                      if sys.argv[1] == "first" else kernels.total.py_func(a) * 3.0),
           "public": kernels.total(a),
           "linked_address": linked_address(kernels.total.internal),
           "hits": int(sum(kernels.total.internal.stats.cache_hits.values()))}
    try:
        kernels.first(a, -1)
    except ValueError as error:
        out["raised"] = str(error)
    print(json.dumps(out))
''')


def _child(folder: Path, cache: Path, entry: str) -> dict:
    # This checkout's package first (the test may run from a worktree beside an install).
    env = dict(os.environ, SPURDYN_CACHE_DIR=str(cache), PYTHONPATH=os.pathsep.join(
        [str(folder), str(Path(linking.__file__).parents[1])]))
    env.pop("NUMBA_CACHE_DIR", None)
    done = subprocess.run([sys.executable, "-c", CHILD, entry], env=env, cwd=folder,
                          capture_output=True, text=True, check=True)
    return json.loads(done.stdout.splitlines()[-1])


@pytest.mark.slow
def test_linked_kernels_compute_raise_and_are_read_from_the_cache(tmp_path: Path) -> None:
    (tmp_path / "kernels.py").write_text(KERNELS)
    cache = tmp_path / "cache"
    one = _child(tmp_path, cache, "first")
    assert one["entry"] == pytest.approx(one["python"], rel=1e-14)
    assert one["raised"] == "negative index"
    assert one["linked_address"] == 0            # never emitted on its own (Numba's: > 0)
    assert one["hits"] == 0
    # A new process compiling another entry links ``total`` read from the disk cache.
    two = _child(tmp_path, cache, "second")
    assert two["hits"] >= 1
    assert two["entry"] == pytest.approx(two["python"], rel=1e-14)
    assert two["public"] == pytest.approx(one["public"], rel=1e-15)
    assert two["raised"] == "negative index"
