# make fuzz: libFuzzer targets (see unit_test/fuzz/README.md). Included by the top Makefile.
