// armfarm: a batch experiment farm for learning the motor control of simulated robot arms.
#include "runner/cli/command_line.hpp"

int main(int argc, char** argv) { return armfarm::cli::run_main(argc, argv); }
