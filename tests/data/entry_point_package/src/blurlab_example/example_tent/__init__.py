"""The method folder example_tent: method.py declares it (blurlab loads that file itself)."""
