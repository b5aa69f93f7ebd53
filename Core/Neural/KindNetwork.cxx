// KindNetwork.cxx: the kind network (four 3x3 convolutions with batch norm, three max-pools,
// global average, dropout, one linear layer), its training, files and the kind check.
#include "Neural/KindNetwork.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Common/Hash.h"
#include "Design/ExemplarGenerator.h"
#include "Gallery/QueryImage.h"
#include "Neural/NeuralNetworks.h"
#include "Render/RayCaster.h" // ddg::Cancelled

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>

namespace ddg
{
namespace
{
namespace fs = std::filesystem;
namespace nn = torch::nn;
using json = nlohmann::json;

constexpr const char* kFormat = "ddg-kind";

struct KindNetImpl : nn::Module
{
  std::vector<nn::Conv2d> convs;
  std::vector<nn::BatchNorm2d> norms;
  nn::Dropout drop{ nullptr };
  nn::Linear fc{ nullptr };
  explicit KindNetImpl(int classes)
  {
    const int c[] = { 3, 32, 64, 128, 128 };
    for (int i = 0; i < 4; ++i)
    {
      convs.push_back(register_module(
        "conv" + std::to_string(i), nn::Conv2d(nn::Conv2dOptions(c[i], c[i + 1], 3).padding(1))));
      norms.push_back(register_module("norm" + std::to_string(i), nn::BatchNorm2d(c[i + 1])));
    }
    drop = register_module("drop", nn::Dropout(0.3));
    fc = register_module("fc", nn::Linear(128, classes));
  }
  torch::Tensor forward(torch::Tensor x)
  {
    for (int i = 0; i < 4; ++i)
    {
      x = torch::relu(norms[i]->forward(convs[i]->forward(x)));
      if (i < 3)
        x = torch::max_pool2d(x, 2);
    }
    return fc->forward(drop->forward(x.mean({ 2, 3 })));
  }
};
TORCH_MODULE(KindNet);

// Flips, quarter turns, channel order, grey (a fifth of the batch), brightness x [0.8, 1.2].
torch::Tensor augment(torch::Tensor x, std::mt19937_64& rng)
{
  std::uniform_real_distribution<double> u(0, 1);
  if (u(rng) < 0.5)
    x = x.flip({ 3 });
  if (u(rng) < 0.5)
    x = x.flip({ 2 });
  x = torch::rot90(x, static_cast<int64_t>(rng() % 4), { 2, 3 });
  std::vector<int64_t> order{ 0, 1, 2 };
  std::shuffle(order.begin(), order.end(), rng);
  x = x.index_select(1, torch::tensor(order));
  const auto grey = torch::rand({ x.size(0), 1, 1, 1 }) < 0.2;
  x = torch::where(grey, x.mean(1, true).expand_as(x), x);
  x = x * (0.8 + 0.4 * torch::rand({ x.size(0), 1, 1, 1 }));
  return x.clamp(0, 1);
}

// PyTorch's OneCycleLR (cosine, 30 % rising, div 25, final div 1e4) with beta1 0.95 <-> 0.85.
void oneCycle(torch::optim::Adam& opt, double maxLr, int step, int total)
{
  const double rise = 0.3 * total - 1, lo = maxLr / 25, end = lo / 1e4;
  auto cosine = [](double a, double b, double pct)
  { return b + (a - b) / 2 * (1 + std::cos(M_PI * pct)); };
  double lr, beta;
  if (step <= rise)
  {
    const double p = rise > 0 ? step / rise : 1;
    lr = cosine(lo, maxLr, p);
    beta = cosine(0.95, 0.85, p);
  }
  else
  {
    const double p = (step - rise) / std::max(1.0, total - 1 - rise);
    lr = cosine(maxLr, end, std::min(1.0, p));
    beta = cosine(0.85, 0.95, std::min(1.0, p));
  }
  auto& o = static_cast<torch::optim::AdamOptions&>(opt.param_groups()[0].options());
  o.lr(lr).betas({ beta, 0.999 });
}

std::string specKey(DesignSpaceSpec spec)
{
  spec.regions.clear(); // each volume's own
  return designSpaceSpecToJson(spec);
}
} // namespace

struct KindNetwork::Internals
{
  KindNet Net{ nullptr };
  std::vector<std::string> Kinds;
  int Size = 64;
  DesignSpaceSpec Spec;
  double Threshold = 0;
  int ReferenceCount = 128;
  std::uint64_t ReferenceSeed = 99;
  std::uint64_t Identity = 0; // of a loaded network: its weights and how references are drawn
  std::string Training = "{}";

  // Mean class probabilities of framed images (N x 3 x S x S in [0, 1]) over 8 flips / turns.
  torch::Tensor probabilities(const torch::Tensor& x)
  {
    torch::NoGradGuard noGrad;
    Net->eval();
    torch::Tensor sum;
    for (int k = 0; k < 4; ++k)
      for (bool flip : { false, true })
      {
        auto y = torch::rot90(x, k, { 2, 3 });
        if (flip)
          y = y.flip({ 3 });
        const auto p = torch::softmax(Net->forward(y), 1);
        sum = sum.defined() ? sum + p : p;
      }
    return sum / 8;
  }
};

KindNetwork::KindNetwork()
  : In(std::make_unique<Internals>())
{
}
KindNetwork::~KindNetwork() = default;
KindNetwork::KindNetwork(KindNetwork&&) noexcept = default;
KindNetwork& KindNetwork::operator=(KindNetwork&&) noexcept = default;

const std::vector<std::string>& KindNetwork::kinds() const
{
  return In->Kinds;
}
int KindNetwork::imageSize() const
{
  return In->Size;
}
const DesignSpaceSpec& KindNetwork::spec() const
{
  return In->Spec;
}
double KindNetwork::threshold() const
{
  return In->Threshold;
}
void KindNetwork::setThreshold(double t)
{
  if (!(t >= 0 && t <= 1))
    throw Error("kind threshold must lie in [0, 1]");
  In->Threshold = t;
}
std::uint64_t KindNetwork::identity() const
{
  return In->Identity;
}
int KindNetwork::referenceCount() const
{
  return In->ReferenceCount;
}
std::uint64_t KindNetwork::referenceSeed() const
{
  return In->ReferenceSeed;
}
const std::string& KindNetwork::trainingRecord() const
{
  return In->Training;
}

KindNetwork KindNetwork::train(const std::vector<std::string>& names,
  const std::vector<std::string>& dirs, const KindTrainOptions& opt, KindTrainReport* report,
  const std::function<bool(int, double, double)>& progress)
{
  if (names.size() != dirs.size() || names.size() < 2)
    throw Error("the kind network needs two or more named datasets");
  if (opt.epochs < 1 || opt.batch < 2 || !(opt.maxLearningRate > 0) ||
    !(opt.validationShare >= 0 && opt.validationShare < 1))
    throw Error("kind training: epochs >= 1, batch >= 2, learning rate > 0, validation share in "
                "[0, 1) are needed");
  for (size_t i = 0; i < names.size(); ++i)
    if (std::count(names.begin(), names.end(), names[i]) > 1 || names[i].empty())
      throw Error("kind training: the name '" + names[i] + "' is empty or given twice");
  const auto t0 = std::chrono::steady_clock::now();
  neural::setThreads(opt.threads);
  torch::manual_seed(opt.seed);
  std::mt19937_64 rng(opt.seed);

  KindNetwork k;
  k.In->Kinds = names;
  std::vector<torch::Tensor> xs;
  std::vector<int64_t> ys;
  for (size_t c = 0; c < dirs.size(); ++c)
  {
    const ExemplarDataset ds(dirs[c]);
    if (c == 0)
    {
      k.In->Size = ds.size();
      k.In->Spec = ds.spec();
      k.In->Spec.regions.clear();
    }
    else if (ds.size() != k.In->Size || specKey(ds.spec()) != specKey(k.In->Spec))
      throw Error("kind training: dataset '" + dirs[c] + "' has another image size or spec than '" +
        dirs[0] + "' (generate all with one spec and size)");
    const int s = ds.size();
    auto x = torch::empty({ ds.count(), 3, s, s }, torch::kUInt8);
    std::vector<std::uint8_t> rgb, viewport, truth;
    for (int i = 0; i < ds.count(); ++i)
    {
      ds.load(i, rgb, viewport, truth);
      x[i].copy_(torch::from_blob(rgb.data(), { s, s, 3 }, torch::kUInt8).permute({ 2, 0, 1 }));
      ys.push_back(static_cast<int64_t>(c));
    }
    xs.push_back(x);
  }
  const auto X = torch::cat(xs);
  const auto Y = torch::tensor(ys);
  const int64_t n = X.size(0), nv = static_cast<int64_t>(n * opt.validationShare);
  const auto idx = torch::randperm(n);
  const auto Xv = X.index_select(0, idx.slice(0, 0, nv)).to(torch::kFloat32) / 255;
  const auto Yv = Y.index_select(0, idx.slice(0, 0, nv));
  const auto Xt = X.index_select(0, idx.slice(0, nv));
  const auto Yt = Y.index_select(0, idx.slice(0, nv));
  const int64_t nt = Xt.size(0);

  k.In->Net = KindNet(static_cast<int>(names.size()));
  torch::optim::Adam adam(k.In->Net->parameters(),
    torch::optim::AdamOptions(opt.maxLearningRate).weight_decay(opt.weightDecay));
  const int stepsPerEpoch = static_cast<int>((nt + opt.batch - 1) / opt.batch);
  const int total = opt.epochs * stepsPerEpoch;
  int step = 0;
  double accuracy = 0;
  for (int epoch = 0; epoch < opt.epochs; ++epoch)
  {
    k.In->Net->train();
    const auto perm = torch::randperm(nt);
    double lossSum = 0;
    for (int64_t i = 0; i < nt; i += opt.batch)
    {
      const auto b = perm.slice(0, i, std::min(nt, i + opt.batch));
      const auto x = augment(Xt.index_select(0, b).to(torch::kFloat32) / 255, rng);
      const auto loss =
        torch::nn::functional::cross_entropy(k.In->Net->forward(x), Yt.index_select(0, b));
      oneCycle(adam, opt.maxLearningRate, step++, total);
      adam.zero_grad();
      loss.backward();
      adam.step();
      lossSum += loss.item<double>() * static_cast<double>(b.size(0));
    }
    if (nv > 0)
    {
      torch::NoGradGuard noGrad;
      k.In->Net->eval();
      int64_t right = 0;
      for (int64_t i = 0; i < nv; i += 512)
      {
        const auto out = k.In->Net->forward(Xv.slice(0, i, std::min(nv, i + 512)));
        right += out.argmax(1).eq(Yv.slice(0, i, std::min(nv, i + 512))).sum().item<int64_t>();
      }
      accuracy = static_cast<double>(right) / static_cast<double>(nv);
    }
    if (progress && !progress(epoch, lossSum / static_cast<double>(nt), accuracy))
      throw Cancelled();
  }
  k.In->Net->eval();
  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::vector<std::string> datasetNames; // the directories' names (not this machine's paths)
  for (const auto& d : dirs)
    datasetNames.push_back(fs::path(d).filename().string());
  json record{ { "datasets", datasetNames }, { "exemplars", n }, { "validation_exemplars", nv },
    { "validation_accuracy", accuracy }, { "epochs", opt.epochs }, { "batch", opt.batch },
    { "max_learning_rate", opt.maxLearningRate }, { "weight_decay", opt.weightDecay },
    { "seed", opt.seed }, { "seconds", seconds } };
  k.In->Training = record.dump();
  if (report)
  {
    report->trainingExemplars = static_cast<int>(nt);
    report->validationExemplars = static_cast<int>(nv);
    report->validationAccuracy = accuracy;
    report->seconds = seconds;
  }
  return k;
}

void KindNetwork::save(const std::string& dir) const
{
  if (!In->Net)
    throw Error("the kind network has no weights to save");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec)
    throw Error("cannot create the kind network's directory '" + dir + "': " + ec.message());
  fs::remove(fs::path(dir) / "kind.json", ec);
  torch::serialize::OutputArchive ar;
  In->Net->save(ar);
  writeFileAtomic(
    (fs::path(dir) / "kind.pt").string(), neural::serialized(ar), "kind network weights");
  json j{ { "format", kFormat }, { "version", 1 }, { "kinds", In->Kinds },
    { "image_size", In->Size }, { "spec", json::parse(designSpaceSpecToJson(In->Spec)) },
    { "threshold", In->Threshold },
    { "reference", { { "count", In->ReferenceCount }, { "seed", In->ReferenceSeed } } },
    { "training", json::parse(In->Training) } };
  writeFileAtomic((fs::path(dir) / "kind.json").string(), j.dump(2) + "\n", "kind network index");
}

KindNetwork KindNetwork::load(const std::string& dir)
{
  const std::string index = (fs::path(dir) / "kind.json").string();
  if (!fs::exists(index))
    throw Error("'" + dir + "' is not a kind network: it has no kind.json");
  KindNetwork k;
  try
  {
    const json j = json::parse(readTextFile(index, "kind network index"));
    if (j.value("format", "") != kFormat || j.value("version", 0) != 1)
      throw Error("not a kind network (format \"" + std::string(kFormat) + "\", version 1)");
    k.In->Kinds = j.at("kinds").get<std::vector<std::string>>();
    k.In->Size = j.at("image_size").get<int>();
    if (k.In->Kinds.size() < 2 || k.In->Size < 8 || k.In->Size > 1024)
      throw Error("needs two or more kinds and an image size in 8..1024");
    k.In->Spec = parseDesignSpaceSpec(j.at("spec").dump(), index);
    k.setThreshold(j.at("threshold").get<double>());
    k.In->ReferenceCount = j.at("reference").at("count").get<int>();
    k.In->ReferenceSeed = j.at("reference").at("seed").get<std::uint64_t>();
    if (k.In->ReferenceCount < 1)
      throw Error("reference count must be 1 or more");
    k.In->Training = j.value("training", json::object()).dump();
    k.In->Net = KindNet(static_cast<int>(k.In->Kinds.size()));
    torch::serialize::InputArchive ar;
    const std::string weights = (fs::path(dir) / "kind.pt").string();
    ar.load_from(weights);
    // what a kept reference depends on in the files: the weights, the exemplars' spec, count,
    // seed and size (how they are drawn: KindChecker's probe)
    Fnv1a id;
    const std::string bytes = readTextFile(weights, "kind network weights");
    const std::string how = designSpaceSpecToJson(k.In->Spec) + " " +
      std::to_string(k.In->ReferenceCount) + " " + std::to_string(k.In->ReferenceSeed) + " " +
      std::to_string(k.In->Size);
    id.add(bytes.data(), bytes.size());
    id.add(how.data(), how.size());
    k.In->Identity = id.value();
    k.In->Net->load(ar);
    k.In->Net->eval();
  }
  catch (const Error& e)
  {
    throw Error("kind network '" + dir + "': " + e.what());
  }
  catch (const std::exception& e) // JSON, libtorch
  {
    throw Error("kind network '" + dir + "' is missing or corrupt: " + firstLine(e.what()));
  }
  return k;
}

std::vector<double> KindNetwork::meanProbabilities(const std::vector<Image>& framed) const
{
  if (framed.empty())
    throw Error("no images to name");
  std::vector<torch::Tensor> xs;
  for (const auto& im : framed)
  {
    if (im.width != In->Size || im.height != In->Size)
      throw Error("the kind network takes " + std::to_string(In->Size) + " x " +
        std::to_string(In->Size) + " images");
    xs.push_back(neural::imageToTensor(im, 3));
  }
  const auto x = torch::stack(xs);
  torch::Tensor sum = torch::zeros({ static_cast<int64_t>(In->Kinds.size()) });
  for (int64_t i = 0; i < x.size(0); i += 256)
    sum += In->probabilities(x.slice(0, i, std::min(x.size(0), i + 256))).sum(0);
  sum /= static_cast<double>(x.size(0));
  return std::vector<double>(sum.data_ptr<float>(), sum.data_ptr<float>() + sum.size(0));
}

std::vector<double> KindNetwork::pictureProbabilities(const Image& picture) const
{
  Image held;
  return meanProbabilities({ prepareQueryImage(queryPicture(picture, held), In->Size) });
}

std::vector<double> kindReference(const KindNetwork& network, const Volume& volume, int threads,
  const std::function<bool(double)>& progress, int count)
{
  std::random_device rd;
  const fs::path dir =
    fs::temp_directory_path() / ("ddg-kind-" + std::to_string(rd()) + "-" + std::to_string(rd()));
  struct Remove
  {
    fs::path p;
    ~Remove()
    {
      std::error_code ec;
      fs::remove_all(p, ec);
    }
  } remove{ dir };
  GenerateOptions g;
  g.count = count > 0 ? count : network.referenceCount();
  g.size = network.imageSize();
  g.seed = network.referenceSeed();
  g.threads = threads;
  g.screen = true;
  g.viewport = false;
  generateExemplars(volume, network.spec(), dir.string(), g,
    [&](double f) { return !progress || progress(0.95 * f); });
  const ExemplarDataset ds(dir.string());
  std::vector<Image> images;
  for (int i = 0; i < ds.count(); ++i)
    images.push_back(ds.images(i).rgbExp);
  auto p = network.meanProbabilities(images);
  if (progress && !progress(1.0))
    throw Cancelled();
  return p;
}

double bhattacharyya(const std::vector<double>& p, const std::vector<double>& q)
{
  if (p.size() != q.size())
    throw Error("kind probabilities of different lengths");
  double s = 0;
  for (size_t i = 0; i < p.size(); ++i)
    s += std::sqrt(std::max(0.0, p[i]) * std::max(0.0, q[i]));
  return s;
}

KindCheck checkKind(
  const KindNetwork& network, const Image& picture, const std::vector<double>& reference)
{
  const auto p = network.pictureProbabilities(picture);
  KindCheck c;
  c.agreement = bhattacharyya(p, reference);
  c.threshold = network.threshold();
  c.differs = c.agreement < c.threshold;
  auto top = [&](const std::vector<double>& v)
  { return network.kinds()[std::max_element(v.begin(), v.end()) - v.begin()]; };
  c.pictureLike = top(p);
  c.volumeLike = top(reference);
  return c;
}

std::string kindCheckToJson(const KindCheck& c)
{
  return json{
    { "agreement", c.agreement }, { "threshold", c.threshold }, { "differs", c.differs },
    { "picture_like", c.pictureLike }, { "volume_like", c.volumeLike }
  }.dump();
}

std::string describeKindCheck(const KindCheck& c)
{
  char figures[96];
  std::snprintf(
    figures, sizeof figures, "kind agreement %.3f (threshold %.3f): ", c.agreement, c.threshold);
  return figures +
    std::string(c.differs ? "the picture may show a volume of another kind" : "the same kind") +
    "; the picture is most like " + c.pictureLike + ", the volume like " + c.volumeLike;
}

} // namespace ddg
