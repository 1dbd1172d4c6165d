"""Physical constants, once for the whole package."""

GRAVITY = 9.81  # [m s-2] the thesis' g: the scene default, the references and the validations
G_STANDARD = 9.80665  # [m s-2] standard gravity: the unit "g" of records (PEER convention)
