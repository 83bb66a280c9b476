// TEMPORARY STUB: replaced by the real implementation (foundation work in progress).
