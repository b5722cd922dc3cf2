"""What a drawing is made of: the glyphs read off the constraints (`builder`: pins, slots,
blocks on guides, rods, the bodies), the ground's symbols (`ground`), gears and racks
(`gears`), cams (`cams`), springs and dampers (`springs`), and the plane geometry and
user shapes they share (`shapes`)."""
