"""spurdyn: dynamic contact analysis of spur gears by the method of Lee and Jang.

The package follows the order of the work: ``geometry`` (involute teeth and trochoidal
fillets) → ``mesh`` (Q8 tooth meshes) → ``fem`` (elements, assembly, lumped mass) →
``model`` → ``contact`` → ``solver`` → ``integrate`` → ``results`` → ``cli``.
"""

from spurdyn.errors import InputError

__version__ = "0.1.0"

__all__ = ["InputError", "__version__"]
