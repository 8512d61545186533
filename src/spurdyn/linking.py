"""Compiled kernels kept as LLVM IR until an entry links them (used by :mod:`spurdyn.jit`).

Numba optimises every compiled function's module and emits it to machine code, then links
its optimised IR into each caller, where the caller's module is optimised and emitted once
more. Of a kernel that only other kernels call (no wrapper for Python), only the copies in
the entries are ever run: its own optimisation and emission are spent for nothing, at every
level of the call tree. Here such a kernel's library only links its callees' IR into its
own; the entry that links it optimises and emits the whole once (docs/performance.md,
"The first run's compile"). LLVM optimises the whole module either way, so the machine code
computes the same numbers.

This reaches into Numba's code library (``numba.core.codegen``, stable from 0.59 to 0.68);
:data:`AVAILABLE` is False where its parts are not found, and the gate then builds kernels
as Numba does.
"""

from __future__ import annotations

from typing import Any, Callable

import llvmlite.binding as ll
import llvmlite.ir as llvmir
import numba

try:
    from numba.core import compiler
    from numba.core.codegen import JITCodeLibrary
    from numba.core.compiler_lock import require_global_compiler_lock
    AVAILABLE = all(hasattr(JITCodeLibrary, name) for name in (
        "_get_module_for_linking", "_finalize_dynamic_globals", "_raise_if_finalized"))
except ImportError:                                  # pragma: no cover - other Numba
    AVAILABLE = False

__all__ = ["AVAILABLE", "linked_njit"]


class _LinkedOnly(JITCodeLibrary):
    """A kernel's code library that links its callees and stops there (module docstring).

    Its disk cache holds the linked module's bitcode (Numba's "bitcode" form): a later
    process compiling another entry loads it instead of typing and lowering the kernel again.
    """

    def finalize(self) -> None:
        require_global_compiler_lock()
        self._raise_if_finalized()
        seen: set[int] = set()
        for library in self._linking_libraries:
            if id(library) not in seen:
                seen.add(id(library))
                self._reload_init.update(library._reload_init)
                self._final_module.link_in(library._get_module_for_linking(), preserve=True)
        self._finalize_dynamic_globals()
        self._add_environments()
        self._finalized = True

    def _add_environments(self) -> None:
        """Define in the engine the environment pointers of this module that it lacks.

        Numba stores a compiled function's environment in a global of its module once the
        function is compiled; a library that is never emitted has no such global in the
        engine, so it gets a module of those globals alone (nothing to emit). Names the
        engine defines already (an entry this kernel calls) are left to their module.
        """
        engine = self._codegen._engine
        names = [gv.name for gv in self._final_module.global_variables
                 if "NumbaEnv" in gv.name and not engine.is_symbol_defined(gv.name)]
        if not names:
            return
        module = self._codegen._create_empty_module(self.name + ".environments")
        for name in names:
            gv = llvmir.GlobalVariable(module, llvmir.IntType(8).as_pointer(), name=name)
            gv.linkage = "common"
            gv.initializer = llvmir.Constant(gv.type.pointee, None)
        engine.add_module(ll.parse_assembly(str(module)))

    def get_pointer_to_function(self, name: str) -> int:
        # Without wrappers nothing of it is called from Python: no address is asked for.
        self._ensure_finalized()
        return 0

    def serialize_using_object_code(self) -> tuple[str, str, bytes]:
        self._ensure_finalized()
        return (self.name, "bitcode", self._final_module.as_bitcode())


class _LinkedCompiler(compiler.Compiler if AVAILABLE else object):  # type: ignore[misc]
    """Numba's pipeline with its code put in a :class:`_LinkedOnly` library."""

    def compile_extra(self, func: Callable[..., Any]) -> Any:
        if self.state.library is None:
            self.state.library = _LinkedOnly(self.state.targetctx.codegen(), func.__qualname__)
        return super().compile_extra(func)


def linked_njit(fn: Callable[..., Any], **options: Any) -> Any:
    """``numba.njit(**options)(fn)`` without Python's wrappers, its code only linked."""
    options = dict(options, no_cpython_wrapper=True, no_cfunc_wrapper=True)
    if AVAILABLE:
        options["pipeline_class"] = _LinkedCompiler
    return numba.njit(**options)(fn)
