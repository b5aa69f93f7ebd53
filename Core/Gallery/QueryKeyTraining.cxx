// QueryKeyTraining.cxx: the contrastive query key's training — the network's forward and
// backward pass in Eigen (a few hundred thousand weights: Eigen's products are several times
// faster here than libtorch's linear layers on Debian's reference BLAS), stepped by Core's Adam
// with decoupled weight decay (AdamW).
#include "Gallery/QueryKey.h"

#include "Common/Error.h"
#include "Gallery/QueryKeyGelu.h"
#include "Numerics/Adam.h"
#include "Render/RayCaster.h" // ddg::Cancelled

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace ddg
{

namespace
{

using RMat = QueryKeyMatrix;
using CMap = Eigen::Map<const RMat>;

// One pass of a batch through the key's layers (already standardised input), kept for backward.
struct Pass
{
  std::vector<RMat> in;  // each layer's input
  std::vector<RMat> pre; // each layer's output before GELU
  Eigen::VectorXf norm;  // the last layer's row lengths
  RMat key;              // unit rows
};

void forward(const QueryKey& key, RMat x, Pass& p)
{
  const size_t n = key.layers.size();
  p.in.assign(n, RMat());
  p.pre.assign(n, RMat());
  for (size_t l = 0; l < n; ++l)
  {
    p.in[l] = std::move(x);
    RMat y = layerOutput(key.layers[l], p.in[l]);
    p.pre[l] = y;
    if (l + 1 < n)
    {
      geluInPlace(y);
      x = std::move(y);
    }
  }
  p.norm = p.pre.back().rowwise().norm().cwiseMax(1e-12f);
  p.key = p.norm.cwiseInverse().asDiagonal() * p.pre.back();
}

// Adds the gradient of a loss with respect to the layers, given its gradient w.r.t. p.key.
void backward(
  const QueryKey& key, const Pass& p, const RMat& dKey, std::vector<std::vector<float>>& grad)
{
  // through the normalisation: (dk - k (k . dk)) / |y|
  const Eigen::VectorXf along = (p.key.array() * dKey.array()).rowwise().sum();
  RMat dy = p.norm.cwiseInverse().asDiagonal() * (dKey - along.asDiagonal() * p.key);
  for (size_t l = key.layers.size(); l-- > 0;)
  {
    const auto& layer = key.layers[l];
    auto& g = grad[l];
    Eigen::Map<RMat>(g.data(), layer.rows, layer.cols) += dy.transpose() * p.in[l];
    Eigen::Map<Eigen::RowVectorXf>(g.data() + layer.weights.size(), layer.rows) +=
      dy.colwise().sum();
    if (l == 0)
      break;
    const RMat dIn = dy * CMap(layer.weights.data(), layer.rows, layer.cols);
    dy = dIn.array() * geluDerivative(p.pre[l - 1]).array();
  }
}

// InfoNCE both ways over a batch's keys: the other views' (b) rows must pick their own views'
// (a) rows and the other way round. Returns the loss; the gradients w.r.t. a and b into da, db.
double infoNce(const RMat& a, const RMat& b, double temperature, RMat& da, RMat& db)
{
  const auto n = a.rows();
  const float inv = static_cast<float>(1.0 / temperature);
  const RMat logits = b * a.transpose() * inv; // row i: other view i against every own view
  RMat rows = logits, cols = logits;
  double loss = 0;
  for (Eigen::Index i = 0; i < n; ++i)
  {
    const float m = rows.row(i).maxCoeff();
    rows.row(i) = (rows.row(i).array() - m).exp();
    const float s = rows.row(i).sum();
    loss -= std::log(rows(i, i) / s);
    rows.row(i) /= s;
    const float mc = cols.col(i).maxCoeff();
    cols.col(i) = (cols.col(i).array() - mc).exp();
    const float sc = cols.col(i).sum();
    loss -= std::log(cols(i, i) / sc);
    cols.col(i) /= sc;
  }
  RMat g = (rows + cols) / static_cast<float>(n);
  g.diagonal().array() -= 2.0f / static_cast<float>(n);
  db = g * a * inv;
  da = g.transpose() * b * inv;
  return loss / static_cast<double>(n);
}

double batchLoss(const QueryKey& key, const RMat& own, const RMat& other, double temperature,
  std::vector<std::vector<float>>* grad)
{
  Pass pa, pb;
  forward(key, own, pa);
  forward(key, other, pb);
  RMat da, db;
  const double loss = infoNce(pa.key, pb.key, temperature, da, db);
  if (grad)
  {
    grad->resize(key.layers.size());
    for (size_t l = 0; l < key.layers.size(); ++l)
      (*grad)[l].assign(key.layers[l].weights.size() + key.layers[l].bias.size(), 0.0f);
    backward(key, pa, da, *grad);
    backward(key, pb, db, *grad);
  }
  return loss;
}

} // namespace

double contrastiveKeyLoss(const QueryKey& key, const float* own, const float* other, int batch,
  double temperature, std::vector<std::vector<float>>* gradient)
{
  key.validate();
  if (key.mean.empty() || !key.normalized || batch < 2)
    throw Error("the contrastive loss needs a standardised, normalised key and 2+ pairs");
  for (const auto& l : key.layers)
    if (l.bias.size() != static_cast<size_t>(l.rows))
      throw Error("the contrastive loss needs a bias in every layer");
  return batchLoss(key, standardisedLatents(key, own, batch),
    standardisedLatents(key, other, batch), temperature, gradient);
}

QueryKey fitContrastiveQueryKey(const std::vector<float>& own, const std::vector<float>& other,
  int dim, const ContrastiveKeyOptions& o, const std::function<bool(double)>& progress)
{
  if (dim < 1 || own.size() != other.size() || own.size() % static_cast<size_t>(dim) != 0)
    throw Error("a query key's pairs need as many own as other latents, dim values each");
  if (o.hidden < 1 || o.components < 1 || o.epochs < 1 || o.batch < 2 || !(o.temperature > 0) ||
    !(o.learningRate > 0) || o.weightDecay < 0)
    throw Error("the contrastive query key needs positive sizes, epochs, temperature and rate");
  const int n = static_cast<int>(own.size() / static_cast<size_t>(dim));
  if (n < 2 * dim)
    throw Error("a query key needs at least " + std::to_string(2 * dim) + " view pairs, not " +
      std::to_string(n));
  const int batch = std::min(o.batch, n);
  QueryKey key;
  key.method = "contrastive";
  key.dim = dim;
  key.components = o.components;
  key.pairs = n;
  key.normalized = true;
  // standardised by the own latents' spread (what the outline holds)
  const RMat zo = CMap(own.data(), n, dim);
  const Eigen::RowVectorXf mean = zo.colwise().mean();
  const Eigen::RowVectorXf var = (zo.rowwise() - mean).array().square().colwise().mean();
  key.mean.assign(mean.data(), mean.data() + dim);
  for (int c = 0; c < dim; ++c)
    key.scale.push_back(std::sqrt(var(c)) + 1e-6f);
  std::mt19937_64 rng(o.seed);
  int in = dim;
  for (int rows : { o.hidden, o.hidden, o.components }) // libtorch's Linear initialisation
  {
    QueryKeyLayer l;
    l.rows = rows;
    l.cols = in;
    std::uniform_real_distribution<float> u(
      -1.0f / std::sqrt(static_cast<float>(in)), 1.0f / std::sqrt(static_cast<float>(in)));
    l.weights.resize(static_cast<size_t>(rows) * in);
    l.bias.resize(static_cast<size_t>(rows));
    for (auto& w : l.weights)
      w = u(rng);
    for (auto& b : l.bias)
      b = u(rng);
    key.layers.push_back(std::move(l));
    in = rows;
  }
  const RMat xa = standardisedLatents(key, own.data(), n),
             xb = standardisedLatents(key, other.data(), n);
  // AdamW: Core's Adam on every weight and bias in one vector, with decoupled weight decay
  std::vector<double> theta, flatGrad;
  for (const auto& l : key.layers)
  {
    theta.insert(theta.end(), l.weights.begin(), l.weights.end());
    theta.insert(theta.end(), l.bias.begin(), l.bias.end());
  }
  flatGrad.resize(theta.size());
  Adam adam({}, theta.size());
  std::vector<std::vector<float>> grad;
  const int perEpoch = n / batch;
  const double steps = static_cast<double>(o.epochs) * perEpoch;
  std::vector<int> order(static_cast<size_t>(n));
  RMat ba(batch, dim), bb(batch, dim);
  int t = 0;
  for (int epoch = 0; epoch < o.epochs; ++epoch)
  {
    if (progress && !progress(static_cast<double>(epoch) / o.epochs))
      throw Cancelled();
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), rng);
    for (int s = 0; s < perEpoch; ++s)
    {
      for (int r = 0; r < batch; ++r)
      {
        const int i = order[static_cast<size_t>(s * batch + r)];
        ba.row(r) = xa.row(i);
        bb.row(r) = xb.row(i);
      }
      batchLoss(key, ba, bb, o.temperature, &grad);
      const double lr = o.learningRate * 0.5 * (1 + std::cos(M_PI * t / steps));
      ++t;
      size_t at = 0;
      for (const auto& g : grad)
        at = static_cast<size_t>(
          std::copy(g.begin(), g.end(), flatGrad.begin() + at) - flatGrad.begin());
      for (double& p : theta)
        p -= lr * o.weightDecay * p;
      adam.step(theta, flatGrad, lr);
      at = 0;
      for (auto& l : key.layers)
        for (auto* values : { &l.weights, &l.bias })
          for (float& v : *values)
            v = static_cast<float>(theta[at++]);
    }
  }
  key.validate();
  if (progress && !progress(1.0))
    throw Cancelled();
  return key;
}

} // namespace ddg
