namespace mesohex {}  // removed once pipeline.cpp lands
