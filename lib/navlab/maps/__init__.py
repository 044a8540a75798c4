"""navlab.maps: semantic city maps for the SuReNav benchmark (docs/design.md, "Layers").

``osm`` rasterises OpenStreetMap extracts (``load_city``), ``procedural`` generates seeded city tiles,
``tiles`` cuts real cities into held-out test tiles, ``network``/``routing``/``osrm`` give walkable
networks and pedestrian routes, ``perturb`` makes the semi-static changes that block a route,
``queries`` samples start-goal pairs, ``dataset`` builds and loads data/surenav/maps, ``draw`` holds the
opencv drawing helpers.
"""
