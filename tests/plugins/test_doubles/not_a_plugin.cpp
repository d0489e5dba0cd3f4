// A shared library with no shellflow entry symbol.
extern "C" __attribute__((visibility("default"))) int some_function() { return 42; }
