"""Teacher checks for the line-track test: functions of a run's record (see grading.md)."""

from roboscript.grading.record import RunRecord, Verdict
from roboscript.sim.geometry import segment_distance

ALLOWED_MM = 40.0  # the robot's centre may wander this far from the middle of the tape


def stays_on_line(run: RunRecord) -> Verdict:
    """The robot's centre never strays more than 4 cm from the tape."""
    segments = [seg for line in run.world.lines for seg in line.segments]
    worst_mm, worst_t, first_t = 0.0, 0.0, None
    for t, x, y, _heading in run.path:
        off_mm = min(segment_distance(x, y, seg) for seg in segments)
        if off_mm > worst_mm:
            worst_mm, worst_t = off_mm, t
        if off_mm > ALLOWED_MM and first_t is None:
            first_t = t
    margin_mm = ALLOWED_MM - worst_mm
    return Verdict(
        name="stays_on_line",
        passed=margin_mm >= 0,
        margin=f"{'passed' if margin_mm >= 0 else 'failed'} by {abs(margin_mm) / 10:.1f} cm",
        first_violation_s=first_t,
        detail=f"the farthest from the tape was {worst_mm / 10:.1f} cm, at {worst_t:.1f} s",
        margin_value=margin_mm,
        margin_unit="mm",
        relative_margin=margin_mm / ALLOWED_MM,
    )
