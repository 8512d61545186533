"""The validation report ``docs/validation.md`` and its figures, computed from scratch.

Run from the repository root::

    .venv/bin/python docs/validation validation            # runs what is missing, writes all
    .venv/bin/python docs/validation validation --rerun    # ignore the cached runs
    .venv/bin/python docs/validation validation --runs-only
    .venv/bin/python docs/validation validation --sweep    # first the sweeps of section 7

Every number of the page is computed here: the runs of the FE solver, the lumped model
and the momentum/energy bookkeeping on the paper's pair are cached in
``docs/validation_data/<name>.npz`` (git-ignored; a run is redone when its settings
change, or all with ``--rerun``); the sections then write the markdown and the pictures
``docs/figures/validation_*.png``. The first run takes about eight minutes on one core
(52 runs, one after the other); with the cache, about ten seconds.

Modules:

* ``settings``: paths and the settings of the studies (window, meshes, ...);
* ``spurdyn_api``: every name taken from ``spurdyn``, imported there only;
* ``helpers``: pure functions of arrays and number formatting (the markdown table is
  :mod:`validation.common`'s, shared by all pages), tested in
  ``tests/test_validation_script.py``;
* ``runs``: the run list (:class:`~validation.report.runs.Spec`) and its cache;
* ``context``, ``figures``: what the sections share (the runs and the pair's figures;
  plotting);
* ``paper``, ``convergence``, ``physics``, ``lumped``, ``relief``, ``limits``, ``sweep``:
  sections 1 to 7, each a function of the context returning its markdown;
* ``report``: the introduction, the page as a whole and the command line.
"""
