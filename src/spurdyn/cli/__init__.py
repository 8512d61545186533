"""The ``spurdyn`` command line.

``command``: the console entry point; ``main``: the parser and the subcommands;
``run``, ``sweep``, ``stiffness``: ``spurdyn run``, ``spurdyn sweep``, ``spurdyn
stiffness``; ``inputs``: the commands' common inputs (CASE, a picture's target);
``options``: option parsing shared by the subcommands; ``report``: what ``spurdyn info``
reports.
"""
