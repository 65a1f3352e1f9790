"""Dynamics of a closed chain: inverse (loads, closure forces, reactions) and forward runs."""
