"""`python -m usvsim.viewer [SCENARIO] [--waves] [--lap] [--seconds S] [--screenshot PNG]`: the viewer."""

from __future__ import annotations

import argparse


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(prog="python -m usvsim.viewer", description=__doc__)
    parser.add_argument("scenario", nargs="?", default="harbor")
    parser.add_argument("--waves", action="store_true", help="the harbour with a JONSWAP sea (Hs 0.6 m)")
    parser.add_argument("--lap", action="store_true", help="replay the scripted harbour lap")
    parser.add_argument("--seconds", type=float, default=None, help="stop after this much simulated time")
    parser.add_argument("--screenshot", default=None, help="save the last frame as PNG")
    parser.add_argument("--time-scale", type=float, default=1.0)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    import os

    os.environ["MUJOCO_GL"] = "glfw"  # camera sensors beside the window: the same window system (GLX)

    from usvsim.core.errors import UsvsimError
    from usvsim.simulation import Simulation
    from usvsim.viewer import run_viewer
    from usvsim.viewer.demo import HARBOR_LAP, HARBOR_LAP_SECONDS, harbor_with_waves

    try:  # a user's mistake is one line (exit 2), as in `usvsim run --view`
        sim = (
            Simulation(harbor_with_waves(), args.seed)
            if args.waves
            else Simulation.from_scenario(args.scenario, args.seed)
        )
        seconds = args.seconds if args.seconds is not None else (HARBOR_LAP_SECONDS if args.lap else None)
        stats = run_viewer(sim, script=HARBOR_LAP if args.lap else (), max_seconds=seconds,
                           screenshot=args.screenshot, time_scale=args.time_scale)  # fmt: skip
    except (UsvsimError, RuntimeError) as exc:  # RuntimeError: no display
        parser.exit(2, f"usvsim: error: {exc}\n")
    print(
        f"{stats['frames']} frames in {stats['wall_s']:.1f} s ({stats['fps']:.1f} fps), simulated {stats['sim_s']:.1f} s"
    )


if __name__ == "__main__":
    main()
