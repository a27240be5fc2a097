#pragma once
namespace mpmice {
/// Parse the command line and do what it asks. Returns the exit status:
/// 0 success, 2 bad input or command line, 3 a broken invariant during the run.
int run_cli(int argc, char* argv[]);
}  // namespace mpmice
