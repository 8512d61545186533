"""Contact between the deformed flanks: splines, closest-normal pairs, sliding kinematics."""
