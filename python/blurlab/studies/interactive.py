"""Interactive speed-against-accuracy charts for the study report (Plotly, offline).

One chart per scene: a point per configuration, a trace per method (its legend entry toggles
it), the Pareto front drawn, a hover box with the method, its parameters, the time and every
metric. Buttons switch the y axis between the metrics and the time axis between log and linear.
Plotly's JavaScript is embedded in the page once, so the report opens with no network.
`blurlab.studies.plots` keeps the static PNG/SVG charts for papers.
"""

from __future__ import annotations

import json

import pandas as pd

from ..metrics import get, registered
from .plots import charted_metrics, pareto_front

# The reports' page style (the study's report.html, the sequence study's sequence.html).
PAGE_STYLE = (
    "body{font:14px sans-serif;max-width:1100px;margin:2em auto;padding:0 1em}"
    "table{border-collapse:collapse;font-size:12px}td,th{border:1px solid #ccc;padding:2px 6px;"
    "text-align:right}th{background:#eee}img{max-width:100%}"
    ".gallery{display:flex;flex-wrap:wrap;gap:8px}.gallery figure{margin:0;width:260px}"
    ".gallery img{width:260px;display:block}figcaption{font-size:11px}"
)


def _plotly():
    import plotly.graph_objects as go

    return go


def pareto_chart(rows: pd.DataFrame, title: str = ""):
    """A plotly Figure of one scene's rows: total_ms against each metric the rows have."""
    go = _plotly()
    metrics = charted_metrics(rows)
    if not metrics:
        charted = [n for n in registered() if get(n).higher_is_better is not None]
        raise ValueError("blurlab: the rows have none of the charted metrics " + ", ".join(charted))
    first = metrics[0]
    fig = go.Figure()
    for name, group in rows.groupby("method", sort=True):
        hover = [_hover(row, metrics) for _, row in group.iterrows()]
        fig.add_trace(
            go.Scatter(
                x=group["total_ms"],
                y=group[first],
                mode="markers",
                name=name,
                text=hover,
                hovertemplate="%{text}<extra></extra>",
                marker={"size": 9, "opacity": 0.85},
                meta={"metrics": {m: group[m].tolist() for m in metrics}},
            )
        )
    fronts = {m: pareto_front(rows, m) for m in metrics}
    fig.add_trace(
        go.Scatter(
            x=fronts[first]["total_ms"],
            y=fronts[first][first],
            mode="lines",
            name="Pareto front",
            line={"color": "black", "dash": "dot", "shape": "hv"},
            hoverinfo="skip",
        )
    )
    methods = len(fig.data) - 1
    buttons = []
    for metric in metrics:
        ys = [trace.meta["metrics"][metric] for trace in fig.data[:methods]]
        ys.append(fronts[metric][metric].tolist())
        xs = [trace.x for trace in fig.data[:methods]] + [fronts[metric]["total_ms"].tolist()]
        buttons.append(
            {
                "label": metric.upper(),
                "method": "update",
                "args": [{"y": ys, "x": xs}, {"yaxis.title.text": get(metric).axis_title}],
            }
        )
    axis_buttons = [
        {"label": "log time", "method": "relayout", "args": [{"xaxis.type": "log"}]},
        {"label": "linear time", "method": "relayout", "args": [{"xaxis.type": "linear"}]},
    ]
    fig.update_layout(
        title={"text": title, "x": 0.0, "xanchor": "left", "y": 0.98, "yanchor": "top"},
        xaxis={"title": {"text": "ms per frame (the method's passes)"}, "type": "log"},
        yaxis={"title": {"text": get(first).axis_title}},
        height=460,
        margin={"t": 110, "r": 10, "l": 60, "b": 50},
        legend={"title": {"text": "click to hide / show"}},
        updatemenus=[
            {
                "type": "buttons",
                "direction": "right",
                "x": 0.0,
                "y": 1.16,
                "xanchor": "left",
                "buttons": buttons,
                "showactive": True,
            },
            {
                "type": "buttons",
                "direction": "right",
                "x": 1.0,
                "y": 1.16,
                "xanchor": "right",
                "buttons": axis_buttons,
                "showactive": True,
            },
        ],
    )
    return fig


def _hover(row, metrics) -> str:
    params = json.loads(row["params"]) if isinstance(row["params"], str) else row["params"]
    text = ", ".join(f"{k}={v}" for k, v in sorted(params.items())) or "defaults"
    values = "<br>".join(f"{m.upper()} {row[m]:.4g}" for m in metrics)
    return f"<b>{row['method']}</b><br>{text}<br>{row['total_ms']:.4g} ms<br>{values}"


def chart_html(fig, first: bool, element_id: str) -> str:
    """The chart as an HTML fragment; the `first` one of a page carries Plotly's JavaScript
    (inline: no CDN, the report works offline)."""
    return fig.to_html(
        full_html=False,
        include_plotlyjs=bool(first),
        div_id=element_id,
        config={"displaylogo": False, "toImageButtonOptions": {"format": "svg"}},
    )
