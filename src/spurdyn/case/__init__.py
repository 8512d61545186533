"""Case input: what to run, from a preset or a TOML case file (docs/casefile.md).

- :mod:`~spurdyn.case.presets`: the ready-made runs (the paper's four cases and their
  group) and how a CASE argument (preset, group or file) turns into cases;
- :mod:`~spurdyn.case.file`: a whole case file, the ``[run]`` table read into
  :class:`~spurdyn.settings.RunSettings` and checked by the run check, a
  :class:`~spurdyn.case.file.Case` and its dictionary both ways;
- :mod:`~spurdyn.case.pair_tables`: the pair tables (``[gear_a]``, ``[gear_b]``,
  ``[pair]``, ``[mesh]``) read into a :class:`~spurdyn.case.pair_tables.MeshedPair`;
- :mod:`~spurdyn.case.torque`: a torque history from a CSV file or an inline table;
- :mod:`~spurdyn.case.files`: a file the user named, read with a size limit;
- :mod:`~spurdyn.case.source`: where a run setting comes from (an option or the file), and
  its refusal naming the one written.

The package sits above the solvers, because the case file runs the run check
(docs/architecture.md). Its names are served lazily, so that importing the pair tables or
the torque reader does not import the solvers.
"""

from __future__ import annotations

from spurdyn.lazy import lazy_facade

#: Public names and the module each comes from (imported when first asked for).
_EXPORTS = {
    "GROUPS": "presets", "PRESETS": "presets", "Preset": "presets", "is_preset": "presets",
    "preset_case": "presets", "preset_lines": "presets", "resolve_cases": "presets",
    "CASE_CONTACT": "file", "RUN_KEYS": "file", "Case": "file", "case_from_dict": "file",
    "case_from_pair": "file", "case_to_dict": "file", "load_case": "file",
    "read_case_file": "file", "RunSource": "source", "file_torque": "file", "MAX_FILE_BYTES": "files", "read_text": "files",
    "BLANK_KEYS": "pair_tables", "GEAR_KEYS": "pair_tables", "MATERIAL_KEYS": "pair_tables",
    "MESH_KEYS": "pair_tables", "PAIR_KEYS": "pair_tables", "RACK_KEYS": "pair_tables",
    "RELIEF_KEYS": "pair_tables", "TOP_KEYS": "pair_tables", "MeshedPair": "pair_tables",
    "check_keys": "pair_tables", "gear_from_table": "pair_tables", "gear_to_dict": "pair_tables",
    "load_pair": "pair_tables", "material_from_table": "pair_tables",
    "pair_from_dict": "pair_tables", "read_toml": "pair_tables",
    "NEEDED_COLUMNS": "torque", "OPTIONAL_COLUMNS": "torque", "history_from_table": "torque",
    "history_to_table": "torque", "read_history_csv": "torque",
}

__all__ = sorted(_EXPORTS)


# served lazily (spurdyn.lazy); an unknown name is an AttributeError
__getattr__, __dir__ = lazy_facade(__name__, _EXPORTS, globals())
