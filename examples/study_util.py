"""Shared helper of the example studies: run mixcon on a problem file with textual substitutions."""
import os
import subprocess
import sys


def run_variant(mixcon, source, name, out, substitutions=()):
    """Writes <out>/<name>.yaml (the problem file `source` with each (a, b) of `substitutions`
    replaced, failing when `a` is absent), runs mixcon on it with output <out>/<name>, and
    returns that output directory; exits with mixcon's log when the run fails."""
    text = open(source).read()
    for a, b in substitutions:
        if a not in text:
            sys.exit(f"{source}: cannot substitute '{a}'")
        text = text.replace(a, b)
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, name + ".yaml")
    with open(path, "w") as f:
        f.write(text)
    result = os.path.join(out, name)
    log = subprocess.run([mixcon, "run", path, "--output", result], capture_output=True,
                         text=True)
    if log.returncode != 0:
        sys.exit(f"mixcon failed on {name}:\n{log.stdout}\n{log.stderr}")
    return result


def finish_figure(fig, ax, path, xlabel, ylabel, title, legend_size=8):
    """Labels, legend and grid of a study's plot, then saves it as a PNG at `path`."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.legend(fontsize=legend_size)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
