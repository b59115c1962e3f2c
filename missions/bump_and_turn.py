"""Explore a walled room, turning away from walls: the Python twin of bump_and_turn.yaml."""

from roboscript import Drive, Mission, PlayTone, Rotate, state


class BumpAndTurn(Mission):
    """Explore a walled room: drive until something is close ahead or a bumper is hit, back
    off, turn, and carry on. Three turns and it is done.
    """

    world = "square-room"

    forward = state(
        Drive(distance_mm=3000, speed_mm_s=200),
        initial=True,
        timeout_s=20,
        on_done="turn",
        on_failed="back_off",
        on_timeout="lost",
        when=[("bumped", "back_off"), ("wall_ahead", "turn")],
    )
    back_off = state(Drive(distance_mm=-100, speed_mm_s=100), on_done="turn", on_failed="lost")
    turn = state(
        Rotate(angle_deg=120, turn_rate_deg_s=90),
        on_done=[("turned_three_times", "home"), "forward"],
        on_failed="lost",
    )
    home = state(PlayTone(frequency_hz=660, duration_s=0.3), final="success")
    lost = state(PlayTone(frequency_hz=220, duration_s=1.0), final="failure")

    def bumped(self) -> bool:
        """A bump switch is pressed."""
        return self.bumper.any

    def wall_ahead(self) -> bool:
        """Something is closer than 25 cm ahead."""
        return self.range.distance_cm < 25

    def turned_three_times(self) -> bool:
        """The robot has turned three times."""
        return self.visits("turn") >= 3


if __name__ == "__main__":
    BumpAndTurn.main()
