namespace mesohex {}  // removed once the first post stage lands
