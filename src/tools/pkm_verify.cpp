// pkm_verify: command-line verifier (stub until the verifier lands: it parses nothing and says so).
#include <iostream>

int main(int, char**) {
  std::cerr << "pkm_verify: not implemented yet (the verifier is under construction)\n";
  return 4;
}
