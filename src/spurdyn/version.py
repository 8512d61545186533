"""The package version, defined once (``spurdyn.__version__`` re-exports it)."""

__version__ = "0.1.0"
