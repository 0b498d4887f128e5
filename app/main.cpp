// Placeholder entry point; the command line (run, info) is built in app/.
#include <iostream>
int main() { std::cout << "poresph " << PORESPH_VERSION << "\n"; return 0; }
