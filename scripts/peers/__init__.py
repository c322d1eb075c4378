"""The peer bench's parts (scripts/bench_peers.py): timing and pairing,
the closed-form references, and the OpenSeesPy models and cases."""
