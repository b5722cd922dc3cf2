"""Mech's 2D library beyond the basic joints: cams (`cams`) on closed profiles (`profiles`),
gears and racks (`gears`), the joints that bring their own coordinate and the other 2D
constraints (`joints`), and the `Model` methods that declare them (`methods`)."""
