"""Results: the Result object, NetCDF, CSV and ParaView output, pictures."""
