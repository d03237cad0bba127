// CppUTest entry point shared by every suite binary.
// House rule for test files: include standard, Eigen and project headers first and
// CppUTest's last; CppUTest's leak-detection macros redefine `new`.
#include "CppUTest/CommandLineTestRunner.h"

int main(int argc, char** argv) { return CommandLineTestRunner::RunAllTests(argc, argv); }
