namespace mesohex {}  // removed once the first stage lands
