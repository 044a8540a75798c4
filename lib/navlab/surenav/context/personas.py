"""The hidden personas of the context demonstrator: how much each kind of walker tolerates.

Like ``experts.personas`` these numbers define the simulated human; no learner reads them. Each field
is a relaxation cost Psi in metres: the walker relaxes a region when doing so saves more walking than
its Psi. The ranges come from ``shared/notes/anchors.md`` section D (see ``rules`` for the rules they
feed): crossing budgets span the 60-250 m detour inferred from crosswalk spacing (80-100 m), mid-block
crossings beyond ~180 m between signals and "about 3 minutes" (~250 m) of detour; the patch and
corner values are our assumptions (no area threshold or corner saving was measured).
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace


@dataclass(frozen=True)
class ContextPersona:
    name: str
    crossing_budget_m: float  # mid-block road with a sidewalk alongside: jaywalk when the crossing point is this far
    crossing_point_m: float  # road where a sidewalk ends at it, or beside a crosswalk: the usual place to cross
    bypass_m: float  # any soft region bordering a new obstacle: step round it rather than retrace
    small_patch_m2: float  # a grass / parking / rough patch smaller than this is cut through …
    small_patch_m: float  # … at this Psi
    corner_cut_m: float  # a region of a larger patch that touches the walkway: a corner to cut
    interior_m: float  # a region inside a larger patch (touches no walkway): crossed only if nothing else goes
    noise_amplitude_m: float  # hand wobble of the drawn demonstration, metres
    noise_wavelength_m: float  # its typical period along the path


CONTEXT_PERSONAS: tuple[ContextPersona, ...] = (
    ContextPersona("cautious", crossing_budget_m=200.0, crossing_point_m=6.0, bypass_m=4.0, small_patch_m2=150.0,
                   small_patch_m=6.0, corner_cut_m=30.0, interior_m=400.0, noise_amplitude_m=0.4,
                   noise_wavelength_m=14.0),
    ContextPersona("pragmatic", crossing_budget_m=120.0, crossing_point_m=4.0, bypass_m=2.0, small_patch_m2=300.0,
                   small_patch_m=4.0, corner_cut_m=18.0, interior_m=250.0, noise_amplitude_m=0.6,
                   noise_wavelength_m=11.0),
    ContextPersona("hurried", crossing_budget_m=60.0, crossing_point_m=2.0, bypass_m=1.0, small_patch_m2=600.0,
                   small_patch_m=2.0, corner_cut_m=10.0, interior_m=150.0, noise_amplitude_m=0.8,
                   noise_wavelength_m=9.0),
)


def mean_persona(personas: tuple[ContextPersona, ...] = CONTEXT_PERSONAS) -> ContextPersona:
    """Every tolerance averaged over the personas: what a persona-blind rule can know."""
    numbers = {f.name: sum(getattr(p, f.name) for p in personas) / len(personas)
               for f in fields(ContextPersona) if f.name != "name"}
    return replace(personas[0], name="mean", **numbers)
