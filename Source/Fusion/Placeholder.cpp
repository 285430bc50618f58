// Replaced as the module's sources land.
