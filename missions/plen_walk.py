"""Walk the PLEN2 humanoid round a small loop: the Python twin of plen_walk.yaml."""

from roboscript import Mission, Turn, Wait, Walk, state


class PlenWalk(Mission):
    """Walk the PLEN2 humanoid round a small loop: four steps forward, a quarter turn right,
    two steps back, and turn back to face the start. Written for the plen2 robot.
    """

    robot = "plen2"

    forward = state(
        Walk(steps=4), initial=True, timeout_s=10, on_done="turn_right", on_timeout="stuck"
    )
    turn_right = state(Turn(steps=6), timeout_s=15, on_done="back", on_timeout="stuck")
    back = state(Walk(steps=-2), timeout_s=10, on_done="turn_back", on_timeout="stuck")
    turn_back = state(Turn(steps=-6), timeout_s=15, on_done="rest", on_timeout="stuck")
    rest = state(Wait(duration_s=0.5), final="success")
    stuck = state(final="failure")


if __name__ == "__main__":
    PlenWalk.main()
