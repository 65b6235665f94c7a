"""GRU surrogates of the foot forces (DILATE or MSE), the peak GPs, their training and their
store."""
