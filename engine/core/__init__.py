"""The types every layer of the engine shares: fixed-field configuration classes and
integer enums that print their names."""
