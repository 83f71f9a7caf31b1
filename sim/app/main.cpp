// fovsim CLI entry point: the only place that catches fovsim::Error and exits.
#include <cstdio>

int main() {
  std::puts("fovsim: under construction");
  return 0;
}
