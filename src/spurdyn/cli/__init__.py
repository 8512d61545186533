"""The ``spurdyn`` command line."""
