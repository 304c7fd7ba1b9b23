"""``usdksl info SHOT``: what the checker would see in a shot, mesh by mesh."""

import sys

import click

from usdksl.errors import UsdkslInputError
from usdksl.reading.loader import load_shot

from .options import allow_missing_assets_option, parse_time_range


def _time_span(times) -> str:
    if len(times) == 1:
        return f"{times[0]:g}"
    return f"{times[0]:g}..{times[-1]:g}"


@click.command()
@click.argument("shot", type=click.Path(dir_okay=False, path_type=str))
@click.option("--time-range", nargs=2, type=float, default=None, callback=parse_time_range,
              metavar="A B", help="Only the samples inside [A, B] (USD time codes), ends included.")
@allow_missing_assets_option
def info(shot, time_range, allow_missing_assets):
    """Print each mesh of SHOT: faces, vertices, triangles, samples, time range, classification."""
    try:
        loaded = load_shot(shot, time_range=time_range, allow_missing_assets=allow_missing_assets)
    except UsdkslInputError as error:
        click.echo(f"usdksl: error: {error}", err=True)
        sys.exit(UsdkslInputError.exit_code)
    for warning in loaded.warnings:
        click.echo(f"usdksl: warning: {warning}", err=True)

    rows = [(mesh.path, str(mesh.face_count), str(mesh.vertex_count), str(mesh.triangle_count),
             str(mesh.sample_count), _time_span(mesh.times), mesh.kind) for mesh in loaded.meshes]
    header = ("prim", "faces", "vertices", "triangles", "samples", "time", "kind")
    widths = [max(len(row[i]) for row in rows + [header]) for i in range(len(header))]

    def line(row):
        cells = [row[0].ljust(widths[0])] + [cell.rjust(width) for cell, width in
                                             zip(row[1:-1], widths[1:-1])] + [row[-1]]
        return "  ".join(cells)

    click.echo(line(header))
    for row in rows:
        click.echo(line(row))
    instancers = sorted({mesh.instancer for mesh in loaded.meshes if mesh.instancer})
    if instancers:
        count = sum(1 for mesh in loaded.meshes if mesh.instancer)
        click.echo(f"instances: {count} meshes from {len(instancers)} PointInstancer"
                   f"{'s' if len(instancers) != 1 else ''} ({', '.join(instancers)})")
    metadata = loaded.metadata
    click.echo(f"shot: {len(loaded.meshes)} meshes, {len(loaded.times)} time samples, "
               f"time {_time_span(loaded.times)}, "
               f"timeCodesPerSecond {metadata['timeCodesPerSecond']:g}, "
               f"upAxis {metadata['upAxis']}, metersPerUnit {metadata['metersPerUnit']:g}")
