"""The hidden personas of the synthetic pedestrian expert.

These numbers define the simulated human, the way a simulator defines its physics: no learner
reads them, a learner has to recover the behaviour they cause from the demonstrations. Each persona
is one kind of careful walker; a demonstration's persona is drawn (seeded) per start-goal pair.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Persona:
    name: str
    jaywalk_ratio: float  # jaywalk only if the crosswalk route is this many times longer than the jaywalk route
    road_cost: float  # cost per metre of road once jaywalking
    living_street_cost: float  # shared streets: walkable, not pleasant
    parking_cost: float  # preferred to roads
    rough_cost: float  # avoided unless nothing else goes
    crosswalk_cost: float
    grass_edge_m: float  # grass this close to its edge is a corner one cuts …
    grass_edge_cost: float
    small_patch_m2: float  # … and so is all of a grass patch smaller than this
    lawn_cost: float  # deeper inside a wide lawn: not crossed
    noise_amplitude_m: float  # hand wobble, metres
    noise_wavelength_m: float  # hand wobble, typical period along the path


PERSONAS: tuple[Persona, ...] = (
    Persona("cautious", jaywalk_ratio=3.0, road_cost=4.0, living_street_cost=2.0, parking_cost=1.6,
            rough_cost=12.0, crosswalk_cost=1.0, grass_edge_m=1.5, grass_edge_cost=1.3, small_patch_m2=60.0,
            lawn_cost=30.0, noise_amplitude_m=0.4, noise_wavelength_m=14.0),
    Persona("pragmatic", jaywalk_ratio=2.2, road_cost=3.0, living_street_cost=1.6, parking_cost=1.4,
            rough_cost=8.0, crosswalk_cost=1.0, grass_edge_m=2.5, grass_edge_cost=1.2, small_patch_m2=100.0,
            lawn_cost=20.0, noise_amplitude_m=0.6, noise_wavelength_m=11.0),
    Persona("hurried", jaywalk_ratio=1.7, road_cost=2.5, living_street_cost=1.4, parking_cost=1.25,
            rough_cost=6.0, crosswalk_cost=1.0, grass_edge_m=3.0, grass_edge_cost=1.15, small_patch_m2=150.0,
            lawn_cost=12.0, noise_amplitude_m=0.8, noise_wavelength_m=9.0),
)
