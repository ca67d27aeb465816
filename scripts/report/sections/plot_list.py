"""The report's section `plots`: the plots."""
import os

ID = "plots"


def lines(r):
    plots = r.plots
    out = []
    out += ["## Plots", ""]
    for title, path in plots:
        if path:
            out += [f"### {title}", "", f"![{title}](plots/{os.path.basename(path)})", ""]
    return out
