"""``usdksl merge SHOT PART_DIR... --out DIR``: farm chunks of one shot joined into one run's outputs."""

import sys

import click

from usdksl.regions.baseline import read_any_baseline
from usdksl.errors import UsdkslInputError
from usdksl.pipeline.files import output_targets
from usdksl.reports.output import write_files
from usdksl.scale.merge import merge_chunks

from .options import parse_time_range


@click.command()
@click.argument("shot", type=click.Path(dir_okay=False, path_type=str))
@click.argument("parts", nargs=-1, required=True, metavar="PART_DIR...",
                type=click.Path(file_okay=False, path_type=str))
@click.option("--out", "out", type=click.Path(path_type=str), default=None,
              help="Directory for the merged files (default: beside SHOT; created when missing).")
@click.option("--json", "json_path", metavar="FILE", default=None,
              help="Also write the JSON report of the merged run; '-' for stdout.")
@click.option("--junit", "junit_path", metavar="FILE", default=None,
              help="Also write the JUnit XML report of the merged run.")
@click.option("--baseline", "baseline", metavar="FILE", default=None,
              help="Contacts accepted earlier (as for check): only new contacts count for the exit code.")
@click.option("--baseline-time-tolerance", type=float, default=None, metavar="T",
              help="Also require a baseline entry's time to be within T time codes of the contact's.")
@click.option("--plot", "plot_path", metavar="FILE.png", default=None,
              help="Also draw the contact timeline (the chunks must have been checked with --last-contact).")
@click.option("--time-range", nargs=2, type=float, default=None, callback=parse_time_range, metavar="A B",
              help="Merge only this part of the shot (USD time codes): the chunks must cover exactly [A, B]. "
                   "Without it they must cover the shot's whole range.")
def merge(shot, parts, out, json_path, junit_path, baseline, baseline_time_tolerance, plot_path, time_range):
    """Join the outputs of `usdksl check SHOT --time-range A B --out PART_DIR` chunks into what one run over
    the union of their ranges writes.

    Refuses (exit 2, one line) chunks that leave a gap, leave out part of the range `usdksl check SHOT`
    checks (or of --time-range, which they must cover exactly), overlap with different answers, or come
    from another shot, usdksl version or set of options. Exit 0 clean, 1 contacts found.
    """
    try:
        targets = output_targets(shot, out, json_path, junit_path, plot_path)
        accepted = None if baseline is None else read_any_baseline(baseline, baseline_time_tolerance)
        result = merge_chunks(shot, parts, targets, accepted, time_range)
        write_files(result.files)
    except UsdkslInputError as error:
        click.echo(f"usdksl: error: {error}", err=True)
        sys.exit(error.exit_code)
    if result.stdout is not None:
        sys.stdout.write(result.stdout)
    chunks = f"{len(parts)} chunk{'s' if len(parts) != 1 else ''}"
    click.echo(f"usdksl: merged {chunks}: {result.summary[len('usdksl: '):]}", err=True)
    sys.exit(result.exit_code)
