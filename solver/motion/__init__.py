"""Motions: keyed frames solved in order, each warm-started, kept from passing through things between them."""
