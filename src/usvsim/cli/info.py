"""`usvsim info FILE`: what a recording holds (topics, types, counts, rates, duration, episodes, compression),
without ROS (`ros2 bag info` needs a ROS install). A file cut short (no summary) is pointed at `usvsim recover`."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from usvsim.cli.errors import fail
from usvsim.core.errors import UsvsimError
from usvsim.messages.envelope import EPISODE_TOPIC


def info(file: Annotated[Path, typer.Argument(help="an MCAP recording")]) -> None:
    """Describe a recording: topics with type, message count and mean rate; duration, episodes, compression."""
    try:
        summary, header, epoch_ns = _read_summary(file)
    except UsvsimError as exc:
        fail(exc)
    stats = summary.statistics
    duration_s = (stats.message_end_time - stats.message_start_time) / 1e9 if stats else 0.0
    counts = stats.channel_message_counts if stats else {}
    kinds = sorted({c.compression or "uncompressed" for c in summary.chunk_indexes})
    episodes = sum(n for cid, n in counts.items() if summary.channels[cid].topic == EPISODE_TOPIC)
    typer.echo(f"{file}: {file.stat().st_size / 1e6:.1f} MB, written by {header.library or 'unknown'} "
               f"(profile {header.profile or 'none'}), {'/'.join(kinds) + ' chunks' if kinds else 'no chunks'}")  # fmt: skip
    typer.echo(f"log time {(stats.message_start_time - epoch_ns) / 1e9:.3f} to {(stats.message_end_time - epoch_ns) / 1e9:.3f}"
               f" s after {_utc(epoch_ns)} ({duration_s:.3f} s), {stats.message_count} messages, {episodes} episode "
               "marker(s)" if stats else "no statistics record")  # fmt: skip
    rows = [("topic", "type", "messages", "per second")]
    for channel in sorted(summary.channels.values(), key=lambda c: c.topic):
        n = counts.get(channel.id, 0)
        schema = summary.schemas.get(channel.schema_id)
        rate = f"{n / duration_s:.2f}" if duration_s > 0 and n > 1 else "-"
        rows.append((channel.topic, schema.name if schema else "?", str(n), rate))
    widths = [max(len(row[k]) for row in rows) for k in range(4)]
    for row in rows:
        typer.echo(
            "  ".join(
                f"{cell:<{w}}" if k < 2 else f"{cell:>{w}}"
                for k, (cell, w) in enumerate(zip(row, widths, strict=True))
            ).rstrip()
        )


def _utc(ns: int) -> str:
    """The recording's epoch (simulation time 0 in log time) as an ISO 8601 UTC date and time."""
    from datetime import UTC, datetime, timedelta

    when = datetime(1970, 1, 1, tzinfo=UTC) + timedelta(microseconds=ns // 1000)
    return when.strftime("%Y-%m-%dT%H:%M:%S.%f")[:-3] + "Z"


def _read_summary(file: Path):
    from mcap.reader import make_reader

    from usvsim.io.mcap_recover import MCAP_MAGIC

    if not file.is_file():
        raise UsvsimError(
            f"{file} is a directory, not a recording" if file.is_dir() else f"no such recording: {file}"
        )
    with file.open("rb") as f:
        head = f.read(len(MCAP_MAGIC))
        if not head:
            raise UsvsimError(f"{file} is empty")
        if not MCAP_MAGIC.startswith(head):  # a file cut inside its magic is a recording cut short
            raise UsvsimError(
                f"{file} is not an MCAP recording (it does not start with the MCAP magic bytes)"
            )
        f.seek(0)
        try:
            reader = make_reader(f)
            header, summary = reader.get_header(), reader.get_summary()
            epochs = [m.metadata.get("log_time_epoch_ns", "") for m in reader.iter_metadata()
                      if m.name == "usvsim"]  # fmt: skip
        except Exception:  # whatever the damage: the file has no readable summary
            summary = header = None
    if summary is None or header is None:
        raise UsvsimError(f"{file} was cut short (no summary: killed, or the disk filled up); "
                          f"'usvsim recover {file}' rewrites what it holds into a complete file")  # fmt: skip
    # a file without the record (older usvsim): log time = simulation time
    return summary, header, int(epochs[0]) if epochs and epochs[0].isdigit() else 0
