"""my_tent meets blurlab's method contract (run: pytest my_tent)."""

from pathlib import Path

import blurlab as bl
from blurlab.methods.contract import check_method, table


def test_the_contract():
    names = bl.load_methods(Path(__file__).parent)
    try:
        checks = check_method(bl.Context(), "my_tent")
        assert all(c.passed is not False for c in checks), table("my_tent", checks)
    finally:
        bl.unload_methods(names)
