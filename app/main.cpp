#include <iostream>

int main() {
  std::cout << "chatterlab\n";
  return 0;
}
