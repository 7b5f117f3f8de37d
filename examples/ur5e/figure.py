"""The case study's figure: the four panels of the paper's Figure 2 (the controller's
moveDiscreteCommand clock, the target X, Y, Z, the joint positions, robotStopped and
moveCompleted), and what the paper could not show: the d-model's state and the super-dense
index reached by every event iteration (exhaustive against stepwise semantics)."""

from __future__ import annotations

from pathlib import Path

from examples.ur5e.analysis import Run


def draw(main: Run, path: Path, stepwise: Run | None = None) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(6, 1, figsize=(12, 14), sharex=True, gridspec_kw={"height_ratios": [1, 1.4, 2, 1.2, 1.8, 1.2]})
    t_col = main.index("time")
    k_col = main.index("superdense")
    end = main.rows[-1][t_col] if main.rows else 0.0

    # 1. the controller's clock
    commands = main.times("controller", "moveDiscreteCommand")
    ax = axes[0]
    _stems(ax, [at[0] for at, _ in commands], 1.0, "C0")
    ax.set_ylabel("moveDiscrete-\nCommand")
    ax.set_yticks([0, 1])
    ax.set_title("(1) controller: clock moveDiscreteCommand", loc="left", fontsize=10)

    # 2. the targets, held between commands
    ax = axes[1]
    for n, axis in enumerate("XYZ"):
        xs, ys = [0.0], [0]
        for at, values in commands:
            xs.append(at[0])
            ys.append(values[f"moveDiscreteCommand.target_{axis}"])
        xs.append(end)
        ys.append(ys[-1])
        ax.step(xs, ys, where="post", label=f"target {axis}", color=f"C{n}")
    ax.set_ylabel("grid cell")
    ax.legend(loc="upper right", ncol=3, fontsize=8)
    ax.set_title("(2) clocked values target_X, target_Y, target_Z", loc="left", fontsize=10)

    # 3. joint positions
    ax = axes[2]
    times = [r[t_col] for r in main.rows]
    for i in range(6):
        ax.plot(times, main.column(f"platform.q{i}"), label=f"q{i}", linewidth=1.0)
    ax.set_ylabel("rad")
    ax.legend(loc="upper right", ncol=6, fontsize=8)
    ax.set_title("(3) platform: joint positions", loc="left", fontsize=10)

    # 4. platform events
    ax = axes[3]
    _stems(ax, [at[0] for at, _ in main.times("platform", "robotStopped")], 1.0, "C2", label="robotStopped")
    _stems(ax, [at[0] for at, _ in main.times("platform", "moveCompleted")], 0.7, "C3", label="moveCompleted")
    ax.set_yticks([0, 1])
    ax.legend(loc="upper right", ncol=2, fontsize=8)
    ax.set_title("(4) platform: robotStopped, moveCompleted (level-sensitive, every sample they hold)", loc="left", fontsize=10)

    # 5. the d-model's state
    ax = axes[4]
    states = main.column(main.state_column)
    names = main.node_names
    shown = sorted({s for s in states if s is not None})
    ax.step(times, states, where="post", color="C4")
    ax.set_yticks(shown)
    ax.set_yticklabels([names.get(s, str(s)) for s in shown], fontsize=8)
    ax.set_title(f"(5) d-model: state of {main.machine} (not visible in the paper)", loc="left", fontsize=10)

    # 6. super-dense index per event iteration
    ax = axes[5]
    for run, colour, label in ((main, "C0", "exhaustive"), (stepwise, "C1", "stepwise")):
        if run is None:
            continue
        last: dict[float, int] = {}
        for r in run.rows:
            last[r[t_col]] = max(last.get(r[t_col], 0), r[k_col])  # type: ignore[arg-type]
        xs = [t for t, k in last.items() if k > 0]
        _stems(ax, xs, [last[t] for t in xs], colour, label=f"{label}: instants per event iteration")
    ax.set_ylabel("last index k")
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title("(6) super-dense index (t, k) reached by each event iteration (not visible in the paper)", loc="left", fontsize=10)
    ax.set_xlabel("time [s]")
    ax.set_xlim(0, end)
    fig.suptitle("UR5e co-simulation with FMI 3.0 clocks: controller, generated d-model, PyBullet platform", fontsize=12)
    fig.tight_layout()
    fig.savefig(path, dpi=110, metadata={"Software": None})
    plt.close(fig)
    return path


def _stems(ax, xs, heights, colour: str, label: str | None = None) -> None:
    if not isinstance(heights, list):
        heights = [heights] * len(xs)
    ax.vlines(xs, 0, heights, colors=colour, linewidth=1.0, label=label)
    ax.plot(xs, heights, "o", color=colour, markersize=2.5)
