"""The kinematic tree and its loop closures: :class:`~feeder.chain.model.closure.ClosedChain`."""
