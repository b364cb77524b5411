"""Plot the reference solutions' paths in follow the path and wildlife (difficulty 0) with the course objects.

    python examples/task_trajectories.py [OUT.png]
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from usvsim.tasks import TASKS, TaskTiming
from usvsim.tasks.solutions import run_trial

COLOURS = {"red": "tab:red", "green": "tab:green", "black": "k", "orange": "tab:orange", "yellow": "gold"}


def main(out: str = "docs/images/tasks_reference.png") -> None:
    fig, axes = plt.subplots(1, 2, figsize=(11, 5))
    for ax, name in zip(axes, ("follow_path", "wildlife")):
        trace: list = []
        report = run_trial(name, 0, 0, TaskTiming(running_s=300.0), trace=trace)
        ax.plot([p[1] for p in trace], [p[2] for p in trace], "b-", lw=1.2)  # the WAM-V's base_link
        for obj in TASKS[name](0, 0).objects():
            x, y, _ = obj["position"]
            ax.plot(x, y, "o", color=COLOURS[obj["color"]], ms=8)
            ax.annotate(obj["name"], (x, y), textcoords="offset points", xytext=(4, 4), fontsize=7)
        ax.set_title(f"{name}: score {report['score']:.1f}, {report['num_collisions']} collisions (WAM-V path blue)")
        ax.set_xlabel("x east (m)")
        ax.set_ylabel("y north (m)")
        ax.set_aspect("equal")
        ax.grid(alpha=0.3)
        ax.margins(0.08, 0.25)  # room for the objects' labels
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print(f"wrote {out}")


if __name__ == "__main__":
    main(*sys.argv[1:])
