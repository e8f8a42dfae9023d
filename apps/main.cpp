#include "apps/commands.h"

int main(int argc, char** argv) {
  return relief::cli::run(argc, argv);
}
