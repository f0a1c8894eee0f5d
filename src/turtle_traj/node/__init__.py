"""The trajectory node: services, parameters and the control timer around the pure core."""
