"""Scenes the engine tests build by hand (the benchmarks keep their own, in benchmarks/)."""


def drum_wall(n_columns: int, n_drums: int, gap: float = 0.05) -> dict:
    """Scene dict of ``n_columns`` columns of ``n_drums`` 0.5 m wide drums, 3 m high, side by
    side ``gap`` [m] apart on one driven base, under a 2 Hz harmonic at 5 m/s2: many bodies
    in a row, each touching only the drums above and below it (and the base)."""
    height = 3.0 / n_drums
    pitch = 0.5 + gap
    span = n_columns * pitch - gap
    bodies = [
        {
            "name": "base",
            "driven": True,
            "box": {"width": span + 12.0, "height": 0.5, "center": [0.0, -0.25]},
        }
    ]
    for c in range(n_columns):
        x = -0.5 * span + 0.25 + c * pitch
        for d in range(n_drums):
            bodies.append(
                {
                    "name": f"c{c}_d{d}",
                    "column": c,
                    "box": {"width": 0.5, "height": height, "center": [x, (d + 0.5) * height]},
                }
            )
    return {
        "name": f"drum_wall_{n_columns}x{n_drums}",
        "bodies": bodies,
        "friction": 0.5,
        "contact": {"model": "point", "k_n": 1.0e10},
        "excitation": {"kind": "harmonic", "frequency": 2.0, "pga": 5.0},
        "solver": {"duration": 0.1},
    }
