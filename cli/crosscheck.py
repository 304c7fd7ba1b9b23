"""``usdksl crosscheck SHOT``: check a continuous result against static frames intersected with Embree."""

import sys

import click

from usdksl.crosscheck.shot import crosscheck_csv_path, crosscheck_shot, write_crosscheck_csv
from usdksl.errors import UsdkslInputError
from usdksl.reading.loader import load_shot

from .options import allow_missing_assets_option, parse_time_range


@click.command()
@click.argument("shot", type=click.Path(dir_okay=False, path_type=str))
@click.option("--frames", default=None, metavar="LIST",
              help="Time codes to check, comma separated: T, A:B (every sample in [A, B]) or A:B:STEP. "
                   "Default: every time sample of the shot.")
@click.option("--contacts", "contacts_file", default=None, type=click.Path(dir_okay=False, path_type=str),
              help="Check this contacts.csv instead of running the continuous check.")
@click.option("--out", "out_dir", default=None, type=click.Path(file_okay=False, path_type=str),
              help="Folder for <stem>.crosscheck.csv (default: the shot's folder).")
@click.option("--time-range", nargs=2, type=float, default=None, callback=parse_time_range,
              metavar="A B", help="Only the samples inside [A, B] (USD time codes), ends included.")
@allow_missing_assets_option
def crosscheck(shot, frames, contacts_file, out_dir, time_range, allow_missing_assets):
    """Intersect static frames of SHOT with Embree and check every intersecting face pair against the
    continuous result: its first contact must come at or before the frame.

    Exit 0 clean, 1 contacts found (and consistent), 2 bad input, 3 the cross-check disagrees.
    """
    try:
        loaded = load_shot(shot, time_range=time_range, allow_missing_assets=allow_missing_assets)
        result = crosscheck_shot(loaded, frames=frames, contacts=contacts_file, time_range=time_range)
        target = write_crosscheck_csv(result, crosscheck_csv_path(shot, out_dir))
    except UsdkslInputError as error:
        click.echo(f"usdksl: error: {error}", err=True)
        sys.exit(UsdkslInputError.exit_code)
    for warning in loaded.warnings:
        click.echo(f"usdksl: warning: {warning}", err=True)
    for line in result.error_lines():
        click.echo(f"usdksl: error: {line}", err=True)
    click.echo(result.summary_line(), err=True)
    click.echo(f"wrote {target}", err=True)
    sys.exit(result.exit_code())
