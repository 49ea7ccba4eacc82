"""my_tent: n taps along the motion, centred on the pixel, tent-weighted (spec.md).
Written by `blurlab new-method`; `blurlab check-method PATH/my_tent` runs the contract."""

from blurlab.methods import Declaration, Param, Pass

from .twin import my_tent

# Each parameter is declared once: its uniform in the shader has the same name.
PARAMS = {
    "taps": Param(9, int, "taps along the motion, centred on the pixel", low=2, high=64),
    "scale": Param(1.0, float, "the blur's length, a fraction of the motion", low=0.0, high=4.0),
}

METHOD = Declaration(
    name="my_tent",
    kind="gather",
    doc="n taps along the motion around the pixel, tent-weighted (spec.md).",
    instant="center",  # the G-buffer time its motion is centred on
    params=PARAMS,
    passes=(Pass("gather", "gather.glsl", tuple(PARAMS)),),
    default_grid={"taps": [5, 9, 17]},
    twin=my_tent,
)
