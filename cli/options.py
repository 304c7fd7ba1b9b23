"""Option parsing shared by the commands."""

import click


def parse_time_range(ctx, param, value):
    """click callback for ``--time-range A B``: a (start, end) tuple in time codes, start <= end."""
    if value is None:
        return None
    start, end = value
    if start > end:
        raise click.BadParameter(f"start {start:g} is after end {end:g}")
    return (start, end)


#: ``--allow-missing-assets``: every command that reads a shot takes it alike.
allow_missing_assets_option = click.option(
    "--allow-missing-assets", is_flag=True,
    help="Read what the stage composes even when a referenced, payloaded, sublayered or clip asset does not "
         "resolve (each is named as not checked). Without it such a stage is exit 2.")
