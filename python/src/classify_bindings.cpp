// classify(points): one cloud through the classify stage's classifier
// (engine/pipeline/point_classifier.hpp), as `sarmap classify` runs it: the
// DGCNN on the cloud's own blocks and the rules after it, or the geometric
// baseline.
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

#include "engine/core/classes.hpp"
#include "engine/pipeline/point_classifier.hpp"
#include "python/src/array_arguments.hpp"
#include "python/src/bindings.hpp"
#include "python/src/config_arguments.hpp"
#include "python/src/errors.hpp"

namespace sarmap::python {

void bind_classify(py::module_& m) {
  m.def(
      "classify",
      [](const py::object& points, const py::object& config) {
        pipeline::MapperConfig c = config_argument(config, "config");
        if (c.classifier.kind == pipeline::ClassifierKind::Labels) {
          value_error("config",
                      "classifier.kind \"labels\" takes the input's labels; classify needs \"dgcnn\" or "
                      "\"geometric\"");
        }
        // One cloud, no sequence: the network runs on the cloud's own blocks
        // (the classifier of the accumulated map would hold labels back for
        // more scans).
        c.classifier.per_scan = true;
        PointBuffer cloud = point_buffer_argument(points, py::none(), "points");
        // The labels line up with the rows given, so a row cannot be dropped
        // as integrate() drops it: a non-finite one is refused instead.
        for (std::size_t i = 0; i < cloud.size(); ++i) {
          if (!std::isfinite(cloud.x()[i]) || !std::isfinite(cloud.y()[i]) || !std::isfinite(cloud.z()[i])) {
            value_error("points", "point " + std::to_string(i) +
                                      " is not finite; classify needs finite coordinates (select them with "
                                      "numpy.isfinite(points).all(axis=1))");
          }
        }
        {
          py::gil_scoped_release release;
          const std::unique_ptr<pipeline::PointClassifier> classifier =
              pipeline::make_point_classifier(c.classifier);
          classifier->classify(cloud);
        }
        // Scores by class id, a column per class (zero for a class the
        // classifier gives no score): a copy, as the engine keeps one array per class.
        py::object scores = py::none();
        if (cloud.score_count() > 0) {
          py::array_t<float> table(
              {static_cast<py::ssize_t>(cloud.size()), static_cast<py::ssize_t>(kClassCount)});
          auto rows = table.mutable_unchecked<2>();
          for (std::size_t k = 0; k < kClassCount; ++k) {
            const std::size_t channel = cloud.find_score(std::string(kClassTable[k].name));
            for (std::size_t i = 0; i < cloud.size(); ++i) {
              rows(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(k)) =
                  channel < cloud.score_count() ? cloud.score(channel)[i] : 0.0f;
            }
          }
          scores = table;
        }
        const py::capsule owner = owner_of(std::move(cloud));
        PointBuffer& kept = *static_cast<PointBuffer*>(owner.get_pointer());
        return py::make_tuple(view_of(kept.labels(), owner), scores);
      },
      py::arg("points"), py::arg("config") = py::none(), R"doc(
Classifies one cloud: (labels, scores), labels an (N,) uint8 array of class ids
(a view of the engine's result, no copy), scores an (N, 6) float32 array by
class id (a copy; None for a classifier without scores, the geometric one).
points: an (N, 3) float32 array or a PointCloud, every coordinate finite.
config: as Mapper's; its classifier section is used (dgcnn with the shipped
model by default, or geometric), always on the cloud's own blocks, as `sarmap
classify` does.)doc");
}

}  // namespace sarmap::python
