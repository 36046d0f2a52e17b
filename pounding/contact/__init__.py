"""Contact laws, their calibration to a coefficient of restitution, and stiffness helpers."""
