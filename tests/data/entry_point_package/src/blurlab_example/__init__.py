"""An example package whose method folder, example_tent, blurlab finds through its entry point."""
