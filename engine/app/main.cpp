// metamer: the command-line tool. Thin: parses arguments and calls the engine.
#include <cstdio>

int main() {
    std::puts("metamer: not yet");
    return 0;
}
