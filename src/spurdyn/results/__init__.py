"""Results: pictures now; NetCDF, CSV and ParaView output with the solver."""
