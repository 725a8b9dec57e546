"""The ``taxelkit`` command line, one module per command group.

:mod:`~taxelkit.cli.app` holds the group and the commands on recordings
(``info``, ``show``, ``sensors``), :mod:`~taxelkit.cli.simulate`,
:mod:`~taxelkit.cli.paper000`, :mod:`~taxelkit.cli.smart`,
:mod:`~taxelkit.cli.live`, :mod:`~taxelkit.cli.convert` and
:mod:`~taxelkit.cli.sources` the others; :mod:`~taxelkit.cli.options` the
option types and :mod:`~taxelkit.cli.common` what they share.
"""

from taxelkit.cli.app import cli, main, run

__all__ = ["cli", "main", "run"]
