"""`usvsim imazu`: write an Imazu encounter scenario for any own ship and speed; the traffic run report."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer


def imazu(
    case: Annotated[int, typer.Argument(help="Imazu encounter 1-22", min=1, max=22)],
    model: Annotated[str, typer.Option(help="own ship: a library vessel (wamv, otter, otter_pvs)")] = "wamv",
    speed: Annotated[float, typer.Option(help="own ship speed, m/s (0.1 to 50; above the vessel's top speed: a "
                                         "warning)")] = 2.0,
    encounter: Annotated[float, typer.Option(help="seconds until the encounter (10 to 1e6)")] = 300.0,
    out: Annotated[Path | None, typer.Option(help="write the scenario here (default: print it)")] = None,
    avoid: Annotated[bool, typer.Option(help="the own ship avoids (COLREG velocity obstacles, docs/traffic.md)")] = False,
) -> None:
    """Write Imazu encounter CASE (own ship heading north, 1-3 targets) as a scenario YAML."""
    from usvsim.cli.errors import fail
    from usvsim.cli.outputs import prepare_file
    from usvsim.core.errors import UsvsimError
    from usvsim.traffic.imazu import imazu_yaml
    from usvsim.vessels.library import LIBRARY

    for option, value, low, high in (("--speed", speed, 0.1, 50.0), ("--encounter", encounter, 10.0, 1e6)):
        if not low <= value <= high:  # NaN too: typer's range check said "should be less than or equal to 50"
            unit, span = ("m/s", "0.1 to 50") if option == "--speed" else ("s", "10 to 1e6")
            fail(f"{option} must be a finite number of {unit} from {span}, got {value:g}")
    if model not in LIBRARY:
        fail(f"--model {model!r}: choose a library vessel ({', '.join(LIBRARY)})")
    text = imazu_yaml(case, model=model, speed_mps=speed, encounter_s=encounter, avoid=avoid)
    try:  # the file must run: fast and long encounters start the ships beyond the 100 km limit of positions
        from usvsim.config import safe_yaml
        from usvsim.config.loader import parse_scenario

        parse_scenario(safe_yaml.parse(text, f"imazu_{case:02d}"), f"imazu_{case:02d}")
    except UsvsimError as exc:
        fail(f"--speed {speed:g} m/s with --encounter {encounter:g} s makes a scenario that cannot run ({exc}); "
             "lower --speed or --encounter")  # fmt: skip
    top = _top_speed_mps(model)
    if speed > top:
        from usvsim.cli.errors import console

        console.print(f"usvsim: warning: --speed {speed:g} m/s is above the {model}'s top speed, {top:.2f} m/s (its "
                      "velocity controller's max_velocity): it will sail slower and reach the encounter late, the "
                      "geometry off", highlight=False, soft_wrap=True, markup=False)  # fmt: skip
    if out is None:
        typer.echo(text, nl=False)
    else:
        try:
            prepare_file(out)
            out.write_text(text)
        except UsvsimError as exc:
            fail(exc)
        except OSError as exc:
            fail(f"cannot write {out}: {exc.strerror or exc}")
        typer.echo(f"wrote Imazu case {case} to {out}; run it with: usvsim run {out} --duration {2 * encounter:g}")


def _top_speed_mps(model: str) -> float:
    """The top surge speed of a library vessel: its velocity controller's max_velocity (the speed at which the
    damping balances the thrusters' full forward thrust), from the vessel built alone."""
    from usvsim.config.loader import parse_scenario
    from usvsim.simulation import Simulation

    data = {"version": 1, "vessels": [{"name": "own", "model": model, "controller": {"type": "velocity"}}]}
    sim = Simulation(parse_scenario(data, "top speed"))
    try:
        return float(sim.controllers["own"].controller.velocity.max_velocity[0])
    finally:
        sim.close()


def _num(x: float | None) -> str:
    return "-" if x is None else f"{x:.1f}"


def _tcpa(r: dict) -> str:
    """TCPA at the end: seconds ahead, 'opening' once the closest point is past, 'steady' without relative
    motion (the range stays)."""
    from usvsim.traffic.awareness import STEADY_MPS

    if r["tcpa_s"] is None:
        return "-"
    if r["relative_speed_mps"] <= STEADY_MPS:
        return "steady"
    return "opening" if r["tcpa_s"] < 0.0 else f"{r['tcpa_s']:.1f}"


def print_report(sim, console) -> None:
    """Per target: the least distance to the own ship during the run and when; the least CPA predicted within
    the TCPA limit and its TCPA ('-': none was, e.g. a target that never closed, or closed so slowly that its
    closest point stayed beyond the limit); the range and TCPA at the end of the run."""
    report = sim.traffic.report()
    if not report:
        return
    from rich.table import Column, Table

    columns = ("target", "min dist (m)", "at t (s)", "min CPA (m)", "at TCPA (s)", "range (m)", "TCPA (s)")
    table = Table(*(Column(c, no_wrap=True) for c in columns), box=None, pad_edge=False)
    for name, r in report.items():
        table.add_row(name, _num(r["min_distance_m"]), _num(r["t_min_distance_s"]), _num(r["min_cpa_m"]),
                      _num(r["tcpa_at_min_cpa_s"]), _num(r["range_m"]), _tcpa(r))  # fmt: skip
    console.print(table)
    for name, r in report.items():  # the table's distances are between reference points, not hulls
        if r["first_contact_s"] is not None:
            console.print(f"hull contact: {name} touched the own ship from t = {r['first_contact_s']:.1f} s to "
                          f"{r['last_contact_s']:.1f} s")  # fmt: skip
    limit = sim.traffic.situation.cfg.tcpa_limit_s
    console.print(f"min CPA: the least CPA predicted while 0 <= TCPA <= {limit:g} s (traffic.awareness.tcpa_limit_s), "
                  "at that TCPA; '-': none was. range, TCPA: at the end of the run ('opening': the closest point is "
                  "past; 'steady': no relative motion).")  # fmt: skip
    _print_avoidance(report, console)


def _print_avoidance(report: dict, console) -> None:
    """When the own ship avoids: per target its COLREG role when it first acted, its alteration then and whether it
    kept to starboard."""
    if not any("encounter" in r for r in report.values()):
        return
    from rich.table import Column, Table

    columns = ("target", "COLREG role", "turn (deg)", "starboard")
    table = Table(*(Column(c, no_wrap=True) for c in columns), box=None, pad_edge=False)
    for name, r in report.items():
        starboard = {True: "yes", False: "NO", None: "-"}[r["starboard"]]
        table.add_row(name, r["encounter"] or "-", _num(r["turn_deg"]), starboard)
    console.print(table)
    console.print("COLREG role, turn: the own ship's role when it first acted for the target and its alteration then "
                  "(deg, starboard +); starboard: no port turn where rules 14, 15 and 17(c) forbid one ('-': no such "
                  "rule, or it never acted).")  # fmt: skip
