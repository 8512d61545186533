"""``spurdyn cache``: where the mode store is, what it holds, and ``--clear`` to empty it
(:mod:`spurdyn.store`)."""

from __future__ import annotations

import argparse

from spurdyn import store


def add_cache_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("cache", help="the store of the gears' modes that runs share: its "
                       "folder and size, or --clear to empty it")
    p.add_argument("--clear", action="store_true", help="remove every entry")
    p.set_defaults(func=cmd_cache)


def cmd_cache(args: argparse.Namespace) -> int:
    folder = store.store_folder()
    if folder is None:
        print(f"mode store: off (SPURDYN_MODE_CACHE={store.OFF})")
        return 0
    if args.clear:
        print(f"mode store: {folder}: {store.clear()} entries removed")
        return 0
    listed = store.entries(folder) if folder.is_dir() else []
    used = sum(p.stat().st_size for p in listed if p.exists())
    print(f"mode store: {folder}: {len(listed)} entries, {used / 1e6:.1f} MB of "
          f"{store.store_size() / 1e6:.0f} MB (SPURDYN_MODE_CACHE_SIZE)")
    return 0


__all__ = ["add_cache_parser", "cmd_cache"]
