namespace mesohex {}  // removed once the first surface file lands
