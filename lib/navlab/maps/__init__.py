"""navlab.maps: semantic city maps for the SuReNav benchmark (see DESIGN.md for the layer).

``osm`` rasterises OpenStreetMap extracts (``load_city``), ``procedural`` generates seeded city tiles,
``tiles`` cuts real cities into held-out test tiles, ``network``/``routing``/``osrm`` give walkable
networks and pedestrian routes, ``dataset`` builds and loads data/surenav/maps, ``draw`` holds the
opencv drawing helpers.
"""
