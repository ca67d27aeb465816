"""The report's section `plots`: the plots."""
import os

from ..common import PLOTS

ID = "plots"


def lines(r):
    plots = r.plots
    out = []
    out += ["## Plots", ""]
    for title, path in plots:
        if path:
            out += [f"### {title}", "", f"![{title}]({PLOTS}/{os.path.basename(path)})", ""]
    return out
