"""Code the tests share: oracles, scene makers, recorded digests, small sweeps."""
