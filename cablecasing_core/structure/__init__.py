"""The structure of both bodies: centerline geometry, cross-sections, the beam element and assembly."""
