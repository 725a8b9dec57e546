"""What ``taxelkit recognize`` prints for recordings: per-track lines, one-object verdicts.

The object table of ``--objects`` is joined to the six here too.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

if TYPE_CHECKING:
    from taxelkit.smart.object_results import ObjectRecognition

__all__ = ["echo_json_parts", "echo_objects", "one_object_json", "one_object_line", "with_objects"]


#: List items written to stdout at once by :func:`echo_json_parts`.
_ITEMS_A_WRITE = 1024


def echo_json_parts(parts: list[tuple[str, Any]]) -> None:
    """Print one JSON object from ``(key, value)`` parts, streaming the long lists.

    The same text as ``click.echo(json.dumps(dict(parts)))`` with the
    iterators as lists (a later part with the same key replaces the value in
    place, as ``dict.update`` does), but a list given as an iterator is
    written an item at a time: a day-long recording's runs and events never
    exist as one document or one string.
    """
    import json
    from collections.abc import Iterator

    merged: dict[str, Any] = {}
    for key, value in parts:
        merged[key] = value
    write = click.echo
    write("{", nl=False)
    for k, (key, value) in enumerate(merged.items()):
        write(("" if k == 0 else ", ") + json.dumps(key) + ": ", nl=False)
        if isinstance(value, Iterator):
            write("[", nl=False)
            batch: list[str] = []
            for i, item in enumerate(value):
                batch.append(("" if i == 0 else ", ") + json.dumps(item))
                if len(batch) == _ITEMS_A_WRITE:
                    write("".join(batch), nl=False)
                    batch = []
            write("".join(batch) + "]", nl=False)
        else:
            write(json.dumps(value), nl=False)
    write("}")


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
