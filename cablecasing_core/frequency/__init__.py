"""The frequency domain: natural frequencies and modes, the apparent-mass transfer function TRFAM."""
