"""``usdksl bench SHOT...``: KSL against every baseline and the ipctk peer on the given shots.

The same code as ``python benchmarks/run.py`` (it lives in the source checkout's benchmarks/ folder,
which is not part of the installed package; matplotlib and ipctk are the ``bench`` extra).
"""

import os
import sys

import click

def _benchmark_folders():
    """Where benchmarks/run.py may be: $USDKSL_BENCHMARKS, beside the package (editable install), or the
    source checkout in the working directory (an installed wheel run from the repository)."""
    configured = os.environ.get("USDKSL_BENCHMARKS")
    if configured:
        yield configured
    yield os.path.join(os.path.dirname(os.path.dirname(os.path.realpath(__file__))), "benchmarks")
    yield os.path.join(os.getcwd(), "benchmarks")


def _benchmark_module():
    folder = next((f for f in _benchmark_folders() if os.path.isfile(os.path.join(f, "run.py"))), None)
    if folder is None:
        raise click.UsageError("usdksl bench needs the source checkout's benchmarks/ folder: run it from the "
                               "repository root or set USDKSL_BENCHMARKS")
    if folder not in sys.path:
        sys.path.insert(0, folder)
    import run  # noqa: E402  (benchmarks/ is a script folder)
    return run


@click.command()
@click.argument("shots", nargs=-1, required=True, type=click.Path(exists=True, dir_okay=False, path_type=str))
@click.option("--methods", default="read,ksl,swept,discrete,discrete x2,ipctk,check", show_default=True,
              help="Comma-separated: read, ksl, swept, discrete, discrete x2/x4/x8, ipctk, check.")
@click.option("--budget", type=float, default=600.0, show_default=True,
              help="Wall seconds per method and shot; methods over budget are reported as skipped.")
@click.option("--json", "json_path", metavar="FILE", default=None, help="Write the result rows as JSON.")
@click.option("--report", "report_dir", metavar="DIR", default=None,
              help="Write REPORT.md, the plots and bench_results.json into DIR.")
def bench(shots, methods, budget, json_path, report_dir):
    """Time KSL, swept, discrete, substepped discrete, ipctk and the USD read on SHOTS; print ratios to KSL."""
    run = _benchmark_module()
    labels = [label.strip() for label in methods.split(",") if label.strip()]
    unknown = [label for label in labels if label not in run.METHODS]
    if unknown:
        raise click.BadParameter(f"unknown methods: {', '.join(unknown)}", param_hint="--methods")
    infos = [run.describe_shot(path) for path in shots]
    rows = run.run_suite(infos, labels, budget, echo=click.echo)
    command = "usdksl bench " + " ".join(sys.argv[2:]) if len(sys.argv) > 2 else "usdksl bench"
    if json_path:
        import json
        with open(json_path, "w") as handle:
            json.dump({"budget_s": budget, "command": command, "rows": rows}, handle, indent=1, default=float)
    if report_dir:
        from report import write_report  # noqa: E402  (imported beside run)
        click.echo(f"wrote {write_report(rows, budget, report_dir, command)}")
