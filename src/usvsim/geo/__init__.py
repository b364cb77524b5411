"""Real places from geospatial files: the geodetic frame, land, seabed, structures and marks."""
