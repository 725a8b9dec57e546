"""``taxelkit sources``: the kinds of live SOURCE, built in and from plugins."""

from __future__ import annotations

import click

__all__ = ["sources"]


@click.command()
def sources() -> None:
    """List the kinds of live SOURCE (KIND:ADDRESS) for 'recognize --live'.

    Packages add kinds through the 'taxelkit.sources' entry-point group.
    """
    from taxelkit.io.source_plugins import source_plugins

    for plugin in source_plugins().values():
        summary = plugin.summary.replace("``", "")
        click.echo(f"{plugin.name:10s} {summary}  [{plugin.origin}]")
