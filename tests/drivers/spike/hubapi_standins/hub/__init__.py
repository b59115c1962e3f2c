"""Stand-in for the SPIKE App 3 ``hub`` module (only what roboscript's agent uses)."""
