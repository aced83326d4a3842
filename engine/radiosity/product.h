// A·B on every core: B's columns (the bands) split among the threads, each an Eigen product of its
// own. Eigen's products run on one core unless built with OpenMP, and the radiosity's are the
// solve's F·[bands] (elements² × bands) and the vertices' W·B: on 2 cores about half the time.
// Tests: engine/radiosity/product_test.cpp.
#pragma once

#include <Eigen/Dense>

namespace metamer::radiosity {

Eigen::MatrixXd timesOnEveryCore(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

}  // namespace metamer::radiosity
