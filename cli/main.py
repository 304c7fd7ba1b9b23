"""Entry point of the ``usdksl`` command: one click group, one module per command."""

import click

from .. import __version__


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="usdksl")
def main():
    """Prove that a USD animation cache is free of interpenetrations."""


def _register():
    from .info import info

    main.add_command(info)
    from .check import check; main.add_command(check)  # noqa: E702
    from .crosscheck import crosscheck; main.add_command(crosscheck)  # noqa: E702
    from .bench import bench; main.add_command(bench)  # noqa: E702
    from .merge import merge; main.add_command(merge)  # noqa: E702


_register()
