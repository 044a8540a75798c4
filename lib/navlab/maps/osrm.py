"""OSRM (Luxen & Vetter, "Real-time routing with OpenStreetMap data", 2011), the router the paper used.

It runs offline here: the ``osrm-bindings`` 26.10.0 wheel (CPython 3.12, manylinux_2_28) carries
self-contained ``osrm-extract`` / ``osrm-contract`` / ``osrm-routed`` binaries and the ``foot.lua``
profile. We fetch the wheel once with pip (into the navlab cache, like the raw inputs), unpack the
binaries and never import it, so it does not depend on the venv's Python version.

What OSRM may walk on is exactly the ``WalkableNetwork`` networkx routes on: the network (already
cleared of dropped and hard-cell edges) is written as an OSM file of footway edges and extracted with
``foot.lua``. The two routers therefore agree on what is walkable by construction, and
``tests/test_maps_osrm.py`` checks that they also agree on the routes. The server listens on
127.0.0.1 only and is stopped when the context closes.
"""

from __future__ import annotations

import json
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request
import zipfile
from pathlib import Path
from typing import Self

import numpy as np
import osmium
from scipy.spatial import cKDTree

from navlab.core.io import DataError, cache_dir
from navlab.maps.network import WalkableNetwork
from navlab.maps.osm import EARTH_RADIUS_M
from navlab.maps.routing import Route

PACKAGE, VERSION = "osrm-bindings", "26.10.0"


def osrm_home() -> Path:
    """Folder holding ``bin/`` and ``share/profiles/`` of the OSRM wheel, fetched once and cached."""
    home = cache_dir() / f"{PACKAGE}-{VERSION}-bin" / "osrm"
    if (home / "bin" / "osrm-routed").is_file():
        return home
    cache_dir().mkdir(parents=True, exist_ok=True)  # unpack beside the cache: the final move is a rename
    with tempfile.TemporaryDirectory(prefix=".osrm-", dir=cache_dir()) as tmp:
        cmd = [sys.executable, "-m", "pip", "download", "--no-deps", "-q", "-d", tmp, "--only-binary=:all:",
               "--python-version", "3.12", "--platform", "manylinux_2_28_x86_64", f"{PACKAGE}=={VERSION}"]
        proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
        wheels = list(Path(tmp).glob("*.whl"))
        if proc.returncode != 0 or not wheels:
            raise DataError(f"could not fetch the OSRM wheel: `{' '.join(cmd)}` failed: {proc.stderr.strip()[-300:]}")
        staging = Path(tmp) / "unpacked"
        with zipfile.ZipFile(wheels[0]) as zf:
            zf.extractall(staging, [m for m in zf.namelist() if m.startswith(("osrm/bin/", "osrm/share/"))])
        for binary in (staging / "osrm" / "bin").iterdir():
            binary.chmod(0o755)
        home.parent.mkdir(parents=True, exist_ok=True)
        shutil.rmtree(home, ignore_errors=True)
        (staging / "osrm").replace(home)
    return home


def _to_lonlat(xy: np.ndarray) -> np.ndarray:
    """Map metres -> degrees near (0, 0), where OSRM's haversine lengths equal the metric ones."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    return np.degrees(np.stack([xy[:, 0], -xy[:, 1]], axis=1) / EARTH_RADIUS_M)


def _to_xy(lonlat: np.ndarray) -> np.ndarray:
    rad = np.radians(np.asarray(lonlat, dtype=float).reshape(-1, 2)) * EARTH_RADIUS_M
    return np.stack([rad[:, 0], -rad[:, 1]], axis=1)


def write_network_osm(network: WalkableNetwork, path: Path) -> None:
    """The network as an OSM file: one node per network node, one ``highway=footway`` way per edge."""
    lonlat = _to_lonlat(network.xy)
    with osmium.SimpleWriter(str(path)) as writer:
        for i, (lon, lat) in enumerate(lonlat):
            writer.add_node(osmium.osm.mutable.Node(id=i + 1, version=1, location=(float(lon), float(lat))))
        for k, (a, b) in enumerate(network.edges):
            writer.add_way(osmium.osm.mutable.Way(id=k + 1, version=1, nodes=[int(a) + 1, int(b) + 1],
                                                  tags={"highway": "footway"}))


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


class OsrmRouter:
    """``with OsrmRouter(network) as router: router.route(start_xy, goal_xy)`` — an osrm-routed server
    on 127.0.0.1 over the network, stopped on exit."""

    def __init__(self, network: WalkableNetwork):
        self.network = network
        self._tree = cKDTree(network.xy)
        self._tmp: tempfile.TemporaryDirectory | None = None
        self._server: subprocess.Popen | None = None
        self.port = 0

    def __enter__(self) -> Self:
        home = osrm_home()
        self._tmp = tempfile.TemporaryDirectory(prefix="navlab-osrm-")
        work = Path(self._tmp.name)
        write_network_osm(self.network, work / "net.osm.pbf")
        for cmd in ([home / "bin" / "osrm-extract", "-p", home / "share" / "profiles" / "foot.lua", "net.osm.pbf"],
                    [home / "bin" / "osrm-contract", "net.osrm"]):
            proc = subprocess.run([str(c) for c in cmd], cwd=work, capture_output=True, text=True, check=False)
            if proc.returncode != 0:
                self.__exit__()
                raise RuntimeError(f"{Path(cmd[0]).name} failed: {proc.stderr.strip()[-300:]}")
        self.port = _free_port()
        self._server = subprocess.Popen(
            [str(home / "bin" / "osrm-routed"), "-i", "127.0.0.1", "-p", str(self.port), "net.osrm"],
            cwd=work, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        for _ in range(300):
            try:
                with socket.create_connection(("127.0.0.1", self.port), timeout=0.2):
                    return self
            except OSError:
                if self._server.poll() is not None:
                    break
                time.sleep(0.1)
        self.__exit__()
        raise RuntimeError(f"osrm-routed did not start on 127.0.0.1:{self.port}")

    def __exit__(self, *exc) -> None:
        if self._server is not None:
            self._server.terminate()
            self._server.wait(timeout=10)
            self._server = None
        if self._tmp is not None:
            self._tmp.cleanup()
            self._tmp = None

    def route(self, start_xy: np.ndarray, goal_xy: np.ndarray) -> Route | None:
        """OSRM's foot route (geometry in map metres, the network node at each point, OSRM's length),
        or None when OSRM finds none."""
        if self._server is None:
            raise RuntimeError("OsrmRouter is not running; use it as `with OsrmRouter(network) as router:`")
        ends = _to_lonlat(np.stack([start_xy, goal_xy]))
        where = ";".join(f"{lon:.7f},{lat:.7f}" for lon, lat in ends)
        url = f"http://127.0.0.1:{self.port}/route/v1/foot/{where}?overview=full&geometries=geojson"
        try:
            with urllib.request.urlopen(url, timeout=30) as reply:
                answer = json.load(reply)
        except urllib.error.HTTPError as err:
            answer = json.load(err)
        if answer.get("code") != "Ok":
            return None
        best = answer["routes"][0]
        xy = _to_xy(best["geometry"]["coordinates"])
        return Route(self._tree.query(xy)[1].astype(np.int64), xy, float(best["distance"]))
