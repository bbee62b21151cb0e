"""Templates and configuration: attributes, their managers, user configuration, JSON
config files, scene datasets."""
