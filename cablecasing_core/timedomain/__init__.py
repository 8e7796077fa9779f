"""The time domain: the Newmark engine with frictional contact, scenarios, runs and support motion."""
