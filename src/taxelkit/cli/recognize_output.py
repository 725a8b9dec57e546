"""What ``taxelkit recognize`` prints for recordings: per-track lines, one-object verdicts.

The object table of ``--objects`` is joined to the six here too.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

if TYPE_CHECKING:
    from taxelkit.smart.object_results import ObjectRecognition

__all__ = ["echo_objects", "one_object_json", "one_object_line", "with_objects"]


def with_objects(config: Any, path: Path) -> Any:
    """``config`` (default Level 3) with the six plus the table's objects and face tactemes."""
    import dataclasses

    from taxelkit.smart.object_table import PAPER_OBJECTS, read_object_table
    from taxelkit.smart.tactemes import TactemeConfig

    table = PAPER_OBJECTS.plus(read_object_table(path).rows)
    base = TactemeConfig() if config is None else config
    return dataclasses.replace(base, face_shapes=True, objects=table)


def echo_objects(objects: ObjectRecognition) -> None:
    """Every track's events, then one line per track and the verdicts (they never disagree)."""
    for e in objects.events:
        value = ", ".join(e.value) if isinstance(e.value, tuple) else e.value
        value = "" if value is None else f"object {value}" if isinstance(value, int) else value
        click.echo(f"frame {e.frame:6d}  {e.t_s:9.3f} s  object {e.track:<3d} {e.kind:11s} {value}")
    accepted = [o for o in objects.objects if o.accepted]
    for o in objects.objects:
        click.echo(o.summary())
        if o.accepted:
            click.echo(f"  why: {o.verdict.sentence()}")
    if not accepted:
        click.echo("identified: nothing (no contact accepted)")
        return
    verdicts = [o.outcome_text() for o in accepted]
    if len(accepted) == 1:
        click.echo(f"identified: {verdicts[0]}")
    else:
        listed = "; ".join(
            f"{v} (object {o.track})" for v, o in zip(verdicts, accepted, strict=True)
        )
        click.echo(f"identified: {listed}")


def one_object_json(objects: ObjectRecognition, config: Any) -> dict[str, Any]:
    """Level 4 over every accepted track's tactemes (``--one-object``), as JSON.

    Keys: ``contacts`` (accepted tracks used), ``identified`` (the object,
    ``"unknown"`` or null), ``candidates`` and ``why`` (null without any
    accepted contact), as for one track.
    """
    from taxelkit.smart.one_object import one_object_verdict, track_contacts

    contacts = track_contacts(objects)
    if not contacts:
        return {"contacts": 0, "identified": None, "candidates": [], "why": None}
    table = None if config is None else config.objects
    verdict = one_object_verdict(contacts, table=table)
    return {
        "contacts": len(contacts),
        "identified": verdict.outcome,
        "candidates": list(verdict.candidates),
        "why": verdict.to_json(),
    }


def one_object_line(doc: dict[str, Any]) -> str:
    """The summary line of ``--one-object`` from :func:`one_object_json`."""
    if doc["why"] is None:
        return "one object: nothing (no contact accepted)"
    return f"one object over {doc['contacts']} contact(s): {doc['why']['sentence']}"
