"""The options that name one trajectory on the command line (`ftfof simulate`, `export`,
`climb`), and the :class:`ftfof.evaluate.pick.Source` they make."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import typer

if TYPE_CHECKING:
    from ftfof.evaluate.pick import Source

BaselineOption = typer.Option(help="polynomial | cycloidal | random_bezier | eps_bezier.")
PointsOption = typer.Option(help="12 control values P3x..P12x, P3z..P12z, comma-separated.")
UnitOption = typer.Option(help="Unit of --points: m or mm.")


def source_of(command: str, names: str, unit: str, required: bool = True, **given: Any) -> Source:
    """The trajectory the command line names (:class:`ftfof.evaluate.pick.Source`): at most one
    of ``given`` (the options ``names`` spells), exactly one where ``required``; typed points
    parsed into metres, their ``unit`` kept for the rules' hints."""
    from ftfof.errors import ParamsError
    from ftfof.evaluate.pick import Source
    from ftfof.robot import parse_points

    chosen = [k for k, v in given.items() if v is not None and v is not False]
    if len(chosen) > 1 or (required and not chosen):
        raise ParamsError(command, f"give {'exactly' if required else 'at most'} one of {names}")
    points = given.get("points")
    return Source(
        row=given.get("row"),
        baseline=given.get("baseline"),
        points=None if points is None else parse_points(points, unit),
        sample=given.get("sample"),
        unit=unit if points is not None else "m",
    )
