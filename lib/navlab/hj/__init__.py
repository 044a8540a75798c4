"""HJ-search (Hu, Siu, Chen 2026): the track's paper tables, built from the planning results of ``reach`` and ``sim``.

The HJ track's own package beside ``surenav`` and ``pacer`` (issue 27 item 1, begun: ``tables``); its
planning, guidance, pruners, scenarios and closed loop still live in ``reach``, ``sim`` and ``metrics``.
"""
