"""Drive a 50 cm square and beep at every corner: the Python twin of square.yaml."""

from roboscript import Drive, Mission, PlayTone, Rotate, state


class Square(Mission):
    """Drive a 50 cm square and beep at every corner."""

    side = state(
        Drive(distance_mm=500, speed_mm_s=150),
        initial=True,
        timeout_s=10,
        on_done="corner",
        on_failed="stuck",
        on_timeout="stuck",
        when=[("bumper_hit", "stuck")],
    )
    corner = state(Rotate(angle_deg=90), on_done="beep", on_failed="stuck")
    beep = state(
        PlayTone(frequency_hz=880, duration_s=0.2),
        on_done=[("four_sides_done", "finished"), "side"],
    )
    stuck = state(PlayTone(frequency_hz=220, duration_s=1.0), final="failure")
    finished = state(final="success")

    def four_sides_done(self) -> bool:
        """True once the robot has driven four sides."""
        return self.visits("side") >= 4

    def bumper_hit(self) -> bool:
        """True while a bump switch is pressed."""
        return self.bumper.any


if __name__ == "__main__":
    Square.main()
