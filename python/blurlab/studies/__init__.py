"""Studies built on the core: sweeps (sweep, evaluation, cluster), the study report (study,
plots), the failure suite (failures) and the hatching measurements (hatching). The core
(context, render, methods, metrics, ...) never imports from here."""
