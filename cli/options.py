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
