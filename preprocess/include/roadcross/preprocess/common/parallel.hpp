// Splitting a loop over the machine's two cores, where the stages' measurements said it pays.
#pragma once

#include <cstddef>
#include <thread>

namespace roadcross::preprocess {

/// Runs body(row) for every row in [0, rows), interleaved over two threads (even rows here, odd
/// rows on a second thread), so that both get rows of every part of a grid. Each call of body
/// must write only its own row's output.
template <typename Body>
void for_rows_on_two_cores(std::size_t rows, const Body& body) {
  std::thread other([&] {
    for (std::size_t row = 1; row < rows; row += 2) body(row);
  });
  for (std::size_t row = 0; row < rows; row += 2) body(row);
  other.join();
}

}  // namespace roadcross::preprocess
