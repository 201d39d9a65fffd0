// SPDX-License-Identifier: MIT
// Temporary entry point while the pipeline is assembled (replaced by the real CLI in this session).
#include <cstdio>
int main() { std::fputs("error: internal: CLI not assembled yet\n", stderr); return 2; }
