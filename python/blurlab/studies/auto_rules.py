"""Fitting `"auto"` rules that generalise (docs/spec.md §23.3): a rule picks a method's
configuration (k, samples, a tile size, ...) from one number of the frame, a motion radius,
by a small threshold table fitted on one set of scenes (random seeds 0..A-1) and judged on
another that it never saw (seeds A..2A-1).

The rule is a table: thresholds t₁ < … < t_{b−1} on a feature split the frames into b bins,
and each bin names the configuration of the method's grid that is within the tolerance of
the best fixed configuration on the most training scenes of that bin (ties: the smaller worst
loss, then the smaller mean loss). The feature is the one, of FEATURES, whose table does best
on the training scenes. Simple enough to print in a line, and to read in the spec.
"""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..core.frame import Frame, moving_speeds
from ..scene import scenes
from ..scene.scenes.features import features_of

# The frame's motion radii a rule may read: the q-th percentile of |M|/2 over the pixels moving
# at least 1 px (px at the frame's size; docs/spec.md §14's r with E = 1 is q = 95).
PERCENTILES = (50, 75, 90, 95, 99)
FEATURES = tuple(f"radius_p{q}" for q in PERCENTILES)
TOLERANCE_DB = 0.25  # "within" the per-scene best fixed configuration
WORST_DB = -1.0  # the bar's worst loss against the best fixed configuration
SHARE = 0.90  # the bar's share of held-out scenes within the tolerance
# The training scenes are split this many ways to choose a rule's feature and bin count: each
# candidate is fitted on all folds but one and judged on that one, in turn.
FOLDS = 5


def frame_features(frame: Frame) -> dict[str, float]:
    """{radius_pQ: the Q-th percentile of |M|/2 over the moving pixels} for PERCENTILES; 0
    for a frame with no pixel moving 1 px. Reads the frame's motion alone."""
    speeds = moving_speeds(frame.motion)
    if not speeds.size:
        return dict.fromkeys(FEATURES, 0.0)
    radii = np.percentile(speeds, PERCENTILES) / 2
    return {name: float(r) for name, r in zip(FEATURES, radii, strict=True)}


def feature_frame(ctx, names, size, instant: str = "center") -> pd.DataFrame:
    """FEATURES per scene (rows by name) of scenes `names`, each rendered by `ctx` at `size`
    at `instant` (the tile filters' and gather_coverage's); the features are computed on
    threads while the next scenes render (scenes.features.features_of)."""
    measured = features_of(ctx, [scenes.get(n) for n in names], size, instant, frame_features)
    return pd.DataFrame(measured, index=list(names), columns=list(FEATURES))


@dataclass(frozen=True)
class RuleTable:
    """A fitted rule: `configs[i]` (a parameter dict, as JSON) for feature values in bin i,
    bin i being thresholds[i-1] <= value < thresholds[i]."""

    feature: str
    thresholds: tuple[float, ...]
    configs: tuple[str, ...]

    def choose(self, value: float) -> str:
        """The configuration (JSON) for a frame whose feature is `value`."""
        return self.configs[int(np.searchsorted(self.thresholds, value, side="right"))]

    def __str__(self) -> str:
        if not self.thresholds:
            return f"every frame: {_short(self.configs[0])}"
        parts = []
        edges = (-np.inf, *self.thresholds, np.inf)
        for low, high, config in zip(edges[:-1], edges[1:], self.configs, strict=True):
            span = f"< {high:.3g}" if low == -np.inf else f">= {low:.3g}"
            if low != -np.inf and high != np.inf:
                span = f"{low:.3g}–{high:.3g}"
            parts.append(f"{self.feature} {span} px: {_short(config)}")
        return "; ".join(parts)


@dataclass(frozen=True)
class ScaledRule:
    """A fitted rule of §14's shape: the configuration with the smallest k ≥ `factor` × the
    frame's `feature` among `configs` (JSON, ascending k, the other parameters alike), or the
    largest k where none reaches it."""

    feature: str
    factor: float
    configs: tuple[str, ...]

    def choose(self, value: float) -> str:
        ks = [json.loads(c)["k"] for c in self.configs]
        index = int(np.searchsorted(ks, self.factor * value, side="left"))
        return self.configs[min(index, len(ks) - 1)]

    def __str__(self) -> str:
        rest = {k: v for k, v in json.loads(self.configs[0]).items() if k != "k"}
        ks = ", ".join(str(json.loads(c)["k"]) for c in self.configs)
        others = "".join(f", {k} = {v}" for k, v in rest.items())
        return f"k = the smallest of {ks} ≥ {self.factor:g} × {self.feature}{others}"


# The factors a ScaledRule may scale its radius by.
FACTORS = (0.5, 0.75, 1.0, 1.5, 2.0, 3.0)


def scaled_rules(columns) -> list[ScaledRule]:
    """Every ScaledRule over configurations `columns` (JSON) that vary k: one per feature,
    factor and setting of the other parameters; none where the configurations have no k."""
    groups: dict[str, list[tuple[int, str]]] = {}
    for config in columns:
        params = json.loads(config)
        if not isinstance(params.get("k"), int):
            return []
        rest = json.dumps({k: v for k, v in params.items() if k != "k"}, sort_keys=True)
        groups.setdefault(rest, []).append((params["k"], config))
    return [
        ScaledRule(feature, factor, tuple(c for _, c in sorted(group)))
        for group in groups.values()
        for feature in FEATURES
        for factor in FACTORS
    ]


def losses(scores: pd.DataFrame) -> pd.DataFrame:
    """Per scene (rows) and configuration (columns, JSON): PSNR − the scene's best PSNR over
    the configurations (≤ 0)."""
    return scores.sub(scores.max(axis=1), axis=0)


def fit(
    scores: pd.DataFrame,
    features: pd.DataFrame,
    bins: int = 4,
    tolerance: float = TOLERANCE_DB,
    folds: int = FOLDS,
) -> RuleTable | ScaledRule:
    """The rule for these scenes: `scores` holds PSNR per scene (rows) and fixed configuration
    (columns, JSON), `features` FEATURES per scene (same rows). Candidates: a RuleTable of
    1..`bins` bins on each feature, judged by `folds`-fold cross-validation over the scenes
    (the fewer bins on a tie) and then fitted on every scene; and, where the configurations
    vary k, every ScaledRule, judged on the scenes (it fits nothing per fold). Bins split at
    the feature's quantiles, so each holds about as many scenes."""
    for name, value in (("bins", bins), ("folds", folds)):
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            raise ValueError(f"blurlab.auto_rules: {name} must be an integer >= 1, not {value!r}")
    if scores.empty or not scores.index.equals(features.index):
        raise ValueError("blurlab.auto_rules: scores and features need the same non-empty scenes")
    loss = losses(scores)
    fold = np.arange(len(loss)) % min(folds, len(loss))
    best = None
    for count in range(1, bins + 1):
        for feature in FEATURES:
            held_out = pd.Series(0.0, index=loss.index)
            for f in np.unique(fold) if fold.max() > 0 else []:
                part = fold != f
                rule = _table(loss[part], features[part], feature, count, tolerance)
                for scene in loss.index[~part]:
                    held_out[scene] = loss.at[scene, rule.choose(features.at[scene, feature])]
            key = _objective(summarize(held_out, tolerance))
            if best is None or key > best[0]:
                best = (key, (loss, features, feature, count, tolerance))
    # A scaled rule fits nothing per fold: its training loss is its held-out loss.
    for rule in scaled_rules(loss.columns):
        key = _objective(assess(rule, scores, features, tolerance))
        if key > best[0]:
            best = (key, rule)
    return _table(*best[1]) if isinstance(best[1], tuple) else best[1]


def _table(loss, features, feature: str, bins: int, tolerance: float) -> RuleTable:
    """The table of `bins` quantile bins of `feature`, each naming its best configuration."""
    values = features[feature].to_numpy(np.float64)
    edges = np.unique(np.quantile(values, np.arange(1, bins) / bins))
    thresholds = tuple(float(t) for t in edges if t > values.min())
    which = np.searchsorted(thresholds, values, side="right")
    configs = tuple(
        _best_config(loss[which == i] if (which == i).any() else loss, tolerance)
        for i in range(len(thresholds) + 1)
    )
    return _merged(RuleTable(feature, thresholds, configs))


def assess(
    rule, scores: pd.DataFrame, features: pd.DataFrame, tolerance: float = TOLERANCE_DB
) -> dict:
    """How `rule` (a RuleTable or ScaledRule, or a fixed configuration as JSON) does on these scenes
    against each scene's best fixed configuration: the share within `tolerance` dB, the
    median and worst loss (dB), and the loss per scene."""
    loss = losses(scores)
    if not isinstance(rule, str):
        chosen = [rule.choose(v) for v in features.loc[scores.index, rule.feature]]
    else:
        chosen = [rule] * len(scores)
    per_scene = pd.Series(
        [loss.at[scene, config] for scene, config in zip(scores.index, chosen, strict=True)],
        index=scores.index,
    )
    return {**summarize(per_scene, tolerance), "chosen": pd.Series(chosen, index=scores.index)}


def summarize(per_scene: pd.Series, tolerance: float = TOLERANCE_DB) -> dict:
    """{within, median_loss, worst_loss, per_scene} of per-scene losses against the best fixed
    configuration (dB, ≤ 0 where the best was among those compared)."""
    return {
        "within": float((per_scene >= -tolerance).mean()),
        "median_loss": float(per_scene.median()),
        "worst_loss": float(per_scene.min()),
        "per_scene": per_scene,
    }


def meets_bar(held_out: dict, builtin_margin: float) -> bool:
    """docs/spec.md §23.3's bar: within TOLERANCE_DB on at least SHARE of the held-out scenes,
    never worse than WORST_DB there, and never worse than today's default by more than
    TOLERANCE_DB on a built-in scene (`builtin_margin`: the rule − the default, worst scene)."""
    return (
        held_out["within"] >= SHARE
        and held_out["worst_loss"] >= WORST_DB
        and builtin_margin >= -TOLERANCE_DB
    )


def score_table(table: pd.DataFrame, method: str, metric: str = "psnr") -> pd.DataFrame:
    """A sweep's rows of `method` as scenes × configurations (the rows' params JSON)."""
    rows = table[table["method"] == method]
    return rows.pivot(index="scene", columns="params", values=metric)


def _merged(rule: RuleTable) -> RuleTable:
    """`rule` with neighbouring bins that name the same configuration made one."""
    thresholds, configs = [], [rule.configs[0]]
    for threshold, config in zip(rule.thresholds, rule.configs[1:], strict=True):
        if config != configs[-1]:
            thresholds.append(threshold)
            configs.append(config)
    return RuleTable(rule.feature, tuple(thresholds), tuple(configs))


def _best_config(loss: pd.DataFrame, tolerance: float) -> str:
    within = (loss >= -tolerance).sum()
    ranked = pd.DataFrame({"within": within, "worst": loss.min(), "mean": loss.mean()})
    ranked = ranked.sort_values(["within", "worst", "mean"], ascending=False, kind="stable")
    return str(ranked.index[0])


def _objective(result: dict) -> tuple:
    return (result["within"], result["worst_loss"], result["median_loss"])


def _short(config: str) -> str:
    return ", ".join(f"{k} = {v}" for k, v in json.loads(config).items())
