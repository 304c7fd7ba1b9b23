"""Entry point of the ``usdksl`` command: one click group, one module per command.

A command's module is imported only when that command runs (or ``--help`` lists it): ``usdksl check``
does not pay for the cross-check's Embree code, the farm merge or the benchmark driver at start-up.
"""

from contextlib import nullcontext
from importlib import import_module

import click

from .import_pause import collector_paused

#: Command name -> the module (relative to this package) that defines it, under the same name.
COMMAND_MODULES = {
    "info": ".info",
    "check": ".check",
    "crosscheck": ".crosscheck",
    "bench": ".bench",
    "merge": ".merge",
}


class LazyCommands(click.Group):
    """A click group that imports a command's module the first time the command is asked for."""

    #: Import it with the cyclic garbage collector paused (cli/import_pause.py). The console script turns
    #: this on for its own process; in-process callers (tests, code embedding the CLI) keep their collector
    #: as it is.
    pause_collector_on_import = False

    def list_commands(self, ctx):
        return sorted(COMMAND_MODULES)

    def get_command(self, ctx, name):
        module_name = COMMAND_MODULES.get(name)
        if module_name is None:
            return None
        with collector_paused() if self.pause_collector_on_import else nullcontext():
            module = import_module(module_name, __package__)
        return getattr(module, name)


def _show_version(ctx, _param, value):
    if not value or ctx.resilient_parsing:
        return
    from usdksl.version import package_version   # the version file the build wrote

    click.echo(f"usdksl, version {package_version()}")
    ctx.exit()


@click.group(cls=LazyCommands, context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--version", is_flag=True, expose_value=False, is_eager=True, callback=_show_version,
              help="Show the version and exit.")
def main():
    """Prove that a USD animation cache is free of interpenetrations."""
