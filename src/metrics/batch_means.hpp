#pragma once
// Batch means: a window split into n equal batches; the spread of the batch values gives the
// standard error of their mean (the batches are taken as independent, so it is a lower bound
// on the error of a correlated series).
#include <cmath>
#include <numeric>
#include <vector>

namespace millwear {

struct BatchMeans {
  double mean = 0.0;
  double rel_sem = 0.0;  // standard error of the mean / mean (0 for n < 2 or mean <= 0)
  double sem = 0.0;      // standard error of the mean (0 for n < 2), any sign of mean
};

inline BatchMeans batch_means(const std::vector<double>& batches) {
  BatchMeans b;
  const int n = static_cast<int>(batches.size());
  if (n == 0) return b;
  b.mean = std::accumulate(batches.begin(), batches.end(), 0.0) / n;
  if (n < 2) return b;
  double var = 0.0;
  for (double x : batches) var += (x - b.mean) * (x - b.mean);
  var /= (n - 1);
  b.sem = std::sqrt(var / n);
  b.rel_sem = b.mean > 0.0 ? std::sqrt(var / n) / b.mean : 0.0;
  return b;
}

}  // namespace millwear
