// vtkDDGReconstructTransferFunction.cxx: converts the input, calls
// ddg::reconstructTransferFunction (or ddg::matchPicture), returns the TF as a table and a preset
// string (and the match's camera, background, figures and masks).
#include "vtkDDGReconstructTransferFunction.h"

#include "DDGFilterInputs.h"
#include "DDGFilterSupport.h"
#include "DDGKindCheck.h"
#include "DDGPieces.h"
#include "DDGVolumeAdaptor.h"
#include "Gallery/Export.h"
#include "Render/RayCaster.h"

#include "Common/FileUtil.h"
#include "Image/Image.h"
#include "Image/ImageMetrics.h"
#include "Reconstruct/CarryLook.h"
#include "Reconstruct/Match.h"
#include "Reconstruct/MatchParts.h"
#include "Reconstruct/Reconstruction.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkIntArray.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <utility>

vtkStandardNewMacro(vtkDDGReconstructTransferFunction);

vtkDDGReconstructTransferFunction::vtkDDGReconstructTransferFunction()
  : KindFingerprint(std::make_shared<ddg::RanksFingerprint>())
{
  this->SetNumberOfOutputPorts(2);
}

vtkDDGReconstructTransferFunction::~vtkDDGReconstructTransferFunction() = default;

void vtkDDGReconstructTransferFunction::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TargetImageFile: " << this->TargetImageFile << "\n";
  os << indent << "ViewFile: " << this->ViewFile << "\n";
  os << indent << "ViewJSON: " << this->ViewJSON << "\n";
  os << indent << "TargetImageData: " << this->TargetImageData.size() << " characters\n";
  os << indent << "OutputFile: " << this->OutputFile << "\n";
  os << indent << "EstimateBackground: " << this->EstimateBackground << "\n";
  os << indent << "Background: " << this->Background[0] << " " << this->Background[1] << " "
     << this->Background[2] << "\n";
  os << indent << "TwoD: " << this->TwoD << "\n";
  os << indent << "Bins: " << this->Bins << "\n";
  os << indent << "Iterations: " << this->Iterations << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "Smoothness: " << this->Smoothness << "\n";
  os << indent << "LearningRate: " << this->LearningRate << "\n";
  os << indent << "MatchPicture: " << this->MatchPicture << "\n";
  os << indent << "CarryLook: " << this->CarryLook << "\n";
  os << indent << "KindNetwork: " << this->KindNetwork << "\n";
  os << indent << "EstimateCamera: " << this->EstimateCamera << "\n";
  os << indent << "InitialTransferFunction: " << this->InitialTransferFunction.size()
     << " characters\n";
  os << indent << "OpacityUnitDistance: " << this->OpacityUnitDistance << "\n";
  os << indent << "CameraCandidates: " << this->CameraCandidates << "\n";
  os << indent << "MinimumOverlap: " << this->MinimumOverlap << "\n";
  os << indent << "EmptySpaceWeight: " << this->EmptySpaceWeight << "\n";
  os << indent << "MaskOverlays: " << this->MaskOverlays << "\n";
  os << indent << "PreviewEvery: " << this->PreviewEvery << "\n";
}

vtkImageData* vtkDDGReconstructTransferFunction::GetPreview()
{
  return this->Preview;
}

namespace
{
vtkSmartPointer<vtkDoubleArray> column(vtkTable* table, const char* name)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  table->AddColumn(a);
  return a;
}

void addString(vtkFieldData* fd, const char* name, const std::string& value)
{
  auto s = vtkSmartPointer<vtkStringArray>::New();
  s->SetName(name);
  s->InsertNextValue(value);
  fd->AddArray(s);
}

/// "Iterations" and "Converged" of a fit.
void addFitFigures(vtkFieldData* fd, const ddg::ReconstructionResult& fit)
{
  auto iterations = vtkSmartPointer<vtkIntArray>::New();
  iterations->SetName("Iterations");
  iterations->InsertNextValue(fit.iterations);
  fd->AddArray(iterations);
  auto converged = vtkSmartPointer<vtkIntArray>::New();
  converged->SetName("Converged");
  converged->InsertNextValue(fit.converged ? 1 : 0);
  fd->AddArray(converged);
}

void addBackground(vtkFieldData* fd, const ddg::View& view)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName("Background");
  const auto& top = view.background2 ? *view.background2 : view.background;
  for (double v :
    { view.background[0], view.background[1], view.background[2], top[0], top[1], top[2] })
    a->InsertNextValue(v);
  fd->AddArray(a);
}

/// The TF's preset name: "DDG <origin>" (the Preset field alone: the same for the same input);
/// with an output file, the volume's array, what made it, the file's stem and the time (Core's
/// exportName), so that every file imports into ParaView.
std::string presetName(
  vtkImageData* input, vtkDataArray* array, const char* origin, const std::string& outputFile)
{
  if (outputFile.empty())
    return std::string("DDG ") + origin;
  if (!array) // the point scalars (vtkDDGAlgorithm's default)
    array = input->GetPointData()->GetScalars();
  const char* arrayName = array ? array->GetName() : nullptr;
  return ddg::exportName(arrayName ? arrayName : "", origin, outputFile);
}

/// Fills `output` with the TF of `result` (rows per bin, its preset or 2D JSON in field data) and
/// returns that JSON; a 2D TF is also described as ParaView's boxes for `caster`'s volume.
std::string writeTable(vtkTable* output, const ddg::ReconstructionResult& result,
  const ddg::RayCaster* caster, const ddg::View& view, const std::string& name)
{
  auto value = column(output, "Value");
  vtkSmartPointer<vtkDoubleArray> gradient;
  if (result.twoD)
    gradient = column(output, "GradientMagnitude");
  auto r = column(output, "Red"), g = column(output, "Green"), b = column(output, "Blue"),
       a = column(output, "Opacity");
  std::string json;
  if (result.twoD)
  {
    const auto& t = result.table2D;
    for (int j = 0; j < t.height; ++j)
      for (int i = 0; i < t.width; ++i)
      {
        const float* e = t.rgba.data() + 4 * (static_cast<size_t>(j) * t.width + i);
        value->InsertNextValue(
          t.valueRange[0] + i * (t.valueRange[1] - t.valueRange[0]) / (t.width - 1));
        gradient->InsertNextValue(
          t.gradientRange[0] + j * (t.gradientRange[1] - t.gradientRange[0]) / (t.height - 1));
        r->InsertNextValue(e[0]);
        g->InsertNextValue(e[1]);
        b->InsertNextValue(e[2]);
        a->InsertNextValue(e[3]);
      }
    ddg::TransferFunction2D tf;
    tf.name = name;
    tf.table = t;
    json = ddg::transferFunction2DToJson(tf);
    addString(output->GetFieldData(), "TransferFunction2D", json);
    if (!caster)
      throw ddg::Error("the first rank holds no cell of the volume: it cannot describe the 2D "
                       "transfer function for ParaView");
    addString(output->GetFieldData(), "ParaViewTransferFunction2D",
      ddg::paraViewTransferFunction2DJson(*caster, tf, view));
  }
  else
  {
    const auto& t = result.table1D;
    for (int i = 0; i < t.width; ++i)
    {
      value->InsertNextValue(t.min + i * (t.max - t.min) / (t.width - 1));
      r->InsertNextValue(t.rgba[4 * i]);
      g->InsertNextValue(t.rgba[4 * i + 1]);
      b->InsertNextValue(t.rgba[4 * i + 2]);
      a->InsertNextValue(t.rgba[4 * i + 3]);
    }
    json = ddg::presetToJson(ddg::resultTransferFunction(result, name).tf1D);
    addString(output->GetFieldData(), "Preset", json);
  }
  return json;
}
} // namespace

int vtkDDGReconstructTransferFunction::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkTable" : "vtkImageData");
  return 1;
}

int vtkDDGReconstructTransferFunction::PieceGhostLevels()
{
  return 1; // every mode works on pieces
}

namespace
{
/// The first rank's image on every rank.
void broadcastImage(const ddg::RankGroup& ranks, ddg::Image& image)
{
  std::vector<float> size = { static_cast<float>(image.width), static_cast<float>(image.height),
    static_cast<float>(image.channels) };
  ranks.broadcast(size);
  ranks.broadcast(image.pixels);
  image.width = static_cast<int>(size[0]);
  image.height = static_cast<int>(size[1]);
  image.channels = static_cast<int>(size[2]);
}

/// The filter's target: the picture (base64 data or a file) at the view, over the background
/// estimated from its border (the view's when they agree) or given.
ddg::ReconstructionTarget targetOf(const std::string& data, const std::string& file,
  const std::string& viewJSON, const std::string& viewFile, bool estimateBackground,
  const double background[3], vtkObject* warnTo)
{
  ddg::ReconstructionTarget target;
  target.image = ddg::filterImage(data, file, "TargetImage");
  target.view = ddg::filterView(viewJSON, viewFile);
  if (target.image.width != target.view.width || target.image.height != target.view.height)
    throw ddg::Error("the target image is " + std::to_string(target.image.width) + " x " +
      std::to_string(target.image.height) + ", the view " + std::to_string(target.view.width) +
      " x " + std::to_string(target.view.height) + ": save the screenshot at the view's size");
  target.image = ddg::inColour(std::move(target.image));
  if (target.image.channels == 3)
  {
    std::optional<std::array<double, 3>> given;
    if (!estimateBackground)
      given = std::array<double, 3>{ background[0], background[1], background[2] };
    const auto bg = ddg::targetBackground(target.image, target.view, given);
    bg.background.applyTo(target.view);
    if (!bg.warning.empty())
      vtkWarningWithObjectMacro(warnTo, << "Background: " << bg.warning << ".");
  }
  return target;
}
} // namespace

void vtkDDGReconstructTransferFunction::Execute(
  vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector)
{
  if (this->CarryLook)
  {
    this->ExecuteCarryLook(input, array, outputVector);
    return;
  }
  if (this->MatchPicture)
  {
    this->ExecuteMatch(input, array, outputVector);
    return;
  }
  if (const ddg::RankGroup* ranks = this->Ranks())
  {
    this->ExecuteOnRanks(*ranks, input, array, outputVector);
    return;
  }
  vtkTable* output = vtkTable::GetData(outputVector, 0);
  const ddg::ReconstructionTarget target = targetOf(this->TargetImageData, this->TargetImageFile,
    this->ViewJSON, this->ViewFile, this->EstimateBackground, this->Background, this);
  const ddg::Volume volume = ddg::toCoreVolume(input, array);
  const ddg::DifferentiableRenderer renderer(volume);
  const auto result = ddg::reconstructTransferFunction(renderer, { target }, this->Options(),
    [this](int step, double, const ddg::ReconstructionResult*)
    {
      this->UpdateProgress(static_cast<double>(step) / this->Iterations);
      return !this->GetAbortExecute();
    });

  const std::string json = writeTable(output, result, &renderer.caster(), target.view,
    presetName(input, array, "reconstruction", this->OutputFile));
  addBackground(output->GetFieldData(), target.view);
  addFitFigures(output->GetFieldData(), result);
  if (!this->OutputFile.empty())
    ddg::writeFileAtomic(this->OutputFile, json, "transfer function");
}

ddg::ReconstructionOptions vtkDDGReconstructTransferFunction::Options() const
{
  ddg::ReconstructionOptions opt;
  opt.twoD = this->TwoD;
  opt.bins = this->Bins;
  opt.iterations = this->Iterations;
  opt.seed = static_cast<unsigned>(this->Seed);
  opt.smoothness = this->Smoothness;
  opt.learningRate = this->LearningRate;
  return opt;
}

void vtkDDGReconstructTransferFunction::ExecuteOnRanks(const ddg::RankGroup& ranks,
  vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector)
{
  // the target as the first rank reads it (the others may not see its paths), on every rank
  ddg::ReconstructionTarget target;
  std::string viewText;
  ranks.step(
    [&]
    {
      if (ranks.rank() != 0)
        return;
      target = targetOf(this->TargetImageData, this->TargetImageFile, this->ViewJSON,
        this->ViewFile, this->EstimateBackground, this->Background, this);
      viewText = ddg::viewToJson(target.view);
    });
  viewText = ranks.broadcast(viewText);
  broadcastImage(ranks, target.image);
  ranks.step(
    [&] { target.view = ddg::parseView(viewText, "the first rank's view"); }); // same everywhere

  // this rank's piece, rendering with the others'
  const ddg::RankVolume pieces =
    ddg::RankVolume::gather(ranks, input, array, this->InputWholeExtent(), false, this->TwoD);
  if (ranks.rank() == 0 && pieces.nonFiniteCount > 0)
    vtkWarningMacro(<< pieces.nonFiniteCount
                    << " NaN/infinite voxels are rendered as their piece's minimum value");
  const auto renderer = ddg::differentiableOnRanks(ranks, pieces);
  // every rank takes the same steps; cancelled when any rank is asked to stop
  ddg::ReconstructionResult result;
  ranks.step(
    [&]
    {
      result = ddg::reconstructTransferFunction(*renderer, { target }, this->Options(),
        [&](int step, double, const ddg::ReconstructionResult*)
        {
          this->UpdateProgress(static_cast<double>(step) / this->Iterations);
          double stop = this->GetAbortExecute() ? 1.0 : 0.0;
          ranks.allMax(&stop, 1);
          return stop == 0.0;
        });
    });
  if (ranks.rank() != 0)
    return; // the first rank's output is the TF
  vtkTable* output = vtkTable::GetData(outputVector, 0);
  const std::string json = writeTable(output, result, pieces.piece ? &renderer->caster() : nullptr,
    target.view, presetName(input, array, "reconstruction", this->OutputFile));
  addBackground(output->GetFieldData(), target.view);
  addFitFigures(output->GetFieldData(), result);
  if (!this->OutputFile.empty())
    ddg::writeFileAtomic(this->OutputFile, json, "transfer function");
}

// --- matching a picture (ddg::matchPicture) ------------------------------------------------------

namespace
{
void addNumbers(vtkFieldData* fd, const char* name, std::initializer_list<double> values)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  for (double v : values)
    a->InsertNextValue(v);
  fd->AddArray(a);
}

/// An image (1 or 3+ channels in [0, 1], row 0 at the top) as an 8-bit point array of `data`
/// (VTK rows go up), which gets the image's dimensions.
void addImageArray(vtkImageData* data, const ddg::Image& image, const char* name, int channels)
{
  data->SetDimensions(image.width, image.height, 1);
  auto a = vtkSmartPointer<vtkUnsignedCharArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(channels);
  a->SetNumberOfTuples(static_cast<vtkIdType>(image.width) * image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < channels; ++c)
      {
        const float v = image.at(x, y, std::min(c, image.channels - 1));
        a->SetTypedComponent(static_cast<vtkIdType>(image.height - 1 - y) * image.width + x, c,
          static_cast<unsigned char>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)));
      }
  data->GetPointData()->AddArray(a);
}

/// A render (premultiplied RGBA) over the view's background (uniform or gradient).
ddg::Image overBackground(const ddg::Image& rgba, const ddg::View& view)
{
  return view.background2 ? ddg::compositeOverBackground(rgba, view.background, *view.background2)
                          : ddg::compositeOverBackground(rgba, view.background);
}

/// The target picture (base64 data or a file), grey and grey-alpha made RGB and RGBA.
ddg::Image pictureOf(const std::string& data, const std::string& file)
{
  return ddg::inColour(ddg::filterImage(data, file, "TargetImage"));
}

/// The target picture and a text that goes with it (`readText`: a view's or its lighting's JSON):
/// read on the first rank and broadcast under MPI (the other ranks may not see the paths).
std::pair<ddg::Image, std::string> firstRankReads(const ddg::RankGroup* ranks,
  const std::string& data, const std::string& file, const std::function<std::string()>& readText)
{
  std::pair<ddg::Image, std::string> read;
  auto readBoth = [&]
  {
    read.first = pictureOf(data, file);
    read.second = readText();
  };
  if (!ranks)
  {
    readBoth();
    return read;
  }
  ranks->step(
    [&]
    {
      if (ranks->rank() == 0)
        readBoth();
    });
  read.second = ranks->broadcast(read.second);
  broadcastImage(*ranks, read.first);
  return read;
}

/// The volume a match or a carried look renders: the whole (builtin), or under MPI this rank's
/// piece rendering with the other ranks' (DDGPieces.h).
struct PictureVolume
{
  std::optional<ddg::RankVolume> pieces;
  std::optional<ddg::Volume> volume;
  std::unique_ptr<ddg::DifferentiableRenderer> renderer;

  PictureVolume(const ddg::RankGroup* ranks, vtkImageData* input, vtkDataArray* array,
    const int wholeExtent[6], bool twoD, vtkObject* warnTo)
  {
    if (!ranks)
    {
      volume.emplace(ddg::toCoreVolume(input, array));
      renderer = std::make_unique<ddg::DifferentiableRenderer>(*volume);
      return;
    }
    pieces.emplace(ddg::RankVolume::gather(*ranks, input, array, wholeExtent, true, twoD));
    if (ranks->rank() == 0 && pieces->nonFiniteCount > 0)
      vtkWarningWithObjectMacro(warnTo, << pieces->nonFiniteCount
                                        << " NaN/infinite voxels are rendered as their piece's "
                                           "minimum value");
    renderer = ddg::differentiableOnRanks(*ranks, *pieces);
  }

  /// The caster that describes a 2D TF for ParaView: none on a first rank without cells.
  const ddg::RayCaster* caster() const
  {
    return !pieces || pieces->piece ? &renderer->caster() : nullptr;
  }

  /// `tf` rendered at `view` as ParaView applies it (collective under MPI: the image on the
  /// first rank, empty elsewhere).
  ddg::Image render(
    const ddg::RankGroup* ranks, const ddg::TransferFunctionFile& tf, const ddg::View& view) const
  {
    return ranks ? ddg::renderOnRanks(*ranks, *pieces, tf, view, {}, {})
                 : renderer->caster().render(tf, view);
  }
};

/// A match's or carried look's progress: cancelled when any rank is asked to stop.
bool keepGoing(vtkAlgorithm* filter, const ddg::RankGroup* ranks)
{
  double stop = filter->GetAbortExecute() ? 1.0 : 0.0;
  if (ranks)
    ranks->allMax(&stop, 1);
  return stop == 0.0;
}

void describeCarriedLook(
  vtkFieldData* fd, const ddg::CarryLookResult& result, const ddg::View& view);

} // namespace

void vtkDDGReconstructTransferFunction::ExecuteMatch(
  vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector)
{
  this->Preview = nullptr;
  // under MPI every rank matches in step over its own piece (Core's match over pieces); the
  // first rank reads the picture and the view (the others may not see its paths) and writes
  const ddg::RankGroup* ranks = this->Ranks();
  const bool first = !ranks || ranks->rank() == 0;
  const bool viewGiven = !this->ViewJSON.empty() || !this->ViewFile.empty();
  const auto read = firstRankReads(ranks, this->TargetImageData, this->TargetImageFile,
    [&]
    { return viewGiven ? ddg::viewToJson(ddg::filterView(this->ViewJSON, this->ViewFile)) : ""; });
  const ddg::Image& picture = read.first;
  const std::string& viewText = read.second;
  std::optional<ddg::View> givenView;
  auto parse = [&]
  {
    if (viewGiven)
      givenView = ddg::parseView(viewText, "the view");
  };
  ranks ? ranks->step(parse) : parse();
  const PictureVolume volume(ranks, input, array, this->InputWholeExtent(), this->TwoD, this);
  const auto& renderer = volume.renderer;

  ddg::MatchOptions opt;
  opt.view = givenView;
  opt.refineGivenView = this->EstimateCamera;
  if (this->OpacityUnitDistance > 0)
    opt.opacityUnitDistance = this->OpacityUnitDistance;
  opt.cameraCandidates = this->CameraCandidates;
  opt.minimumOverlap = this->MinimumOverlap;
  opt.emptySpaceWeight = this->EmptySpaceWeight;
  opt.maskOverlays = this->MaskOverlays;
  if (!this->EstimateBackground)
  {
    opt.background =
      std::array<double, 3>{ this->Background[0], this->Background[1], this->Background[2] };
    if (picture.channels == 3) // on every rank (an error stops all alike), said by the first
    {
      const auto bg = ddg::targetBackground(picture, ddg::View(), opt.background);
      if (!bg.warning.empty() && first)
        vtkWarningMacro(<< "Background: " << bg.warning << ".");
    }
  }
  auto& rec = opt.reconstruction;
  rec.twoD = this->TwoD;
  rec.bins = this->Bins;
  rec.iterations = this->Iterations;
  rec.seed = static_cast<unsigned>(this->Seed);
  rec.smoothness = this->Smoothness;
  rec.learningRate = this->LearningRate;
  rec.snapshotEvery = this->PreviewEvery;
  std::optional<ddg::TransferFunction1D> initialTF;
  if (!this->InitialTransferFunction.empty())
  {
    if (this->TwoD)
      throw ddg::Error("InitialTransferFunction is a 1D preset: it cannot start a 2D match");
    initialTF = ddg::parsePreset(this->InitialTransferFunction, "InitialTransferFunction");
    const auto range = renderer->dataRange();
    rec.initial1D = ddg::bakeTable(*initialTF, range[0], range[1], this->Bins);
  }

  // the preview is shown over the picture's background (when it has one: else matchPicture
  // says why it cannot use the picture)
  ddg::View previewView;
  try
  {
    if (opt.background)
      previewView.background = *opt.background;
    else
      ddg::estimateBackground(ddg::toChannels(picture, 3)).applyTo(previewView);
  }
  catch (const ddg::Error&)
  {
  }
  ddg::MatchResult result;
  auto match = [&]
  {
    result = ddg::matchPicture(*renderer, picture, opt,
      [&](const std::string& stage, double fraction, const ddg::Image* preview)
      {
        if (preview && !preview->empty() && first)
        {
          auto image = vtkSmartPointer<vtkImageData>::New();
          addImageArray(image, overBackground(*preview, previewView), "Image", 3);
          this->Preview = image;
        }
        this->SetProgressText(stage.c_str());
        this->UpdateProgress(std::clamp(fraction, 0.0, 1.0));
        return keepGoing(this, ranks);
      });
  };
  if (ranks)
    ranks->step(match);
  else
    match();
  this->SetProgressText(nullptr);

  // port 0 (the first rank's): the TF, the camera, the background, the figures
  vtkTable* output = vtkTable::GetData(outputVector, 0);
  std::string json;
  auto describe = [&]
  {
    if (!first)
      return;
    json = writeTable(output, result.tf, volume.caster(), result.view,
      presetName(input, array, "match", this->OutputFile));
    vtkFieldData* fd = output->GetFieldData();
    addString(fd, "View", ddg::viewToJson(result.view));
    addNumbers(fd, "CameraEstimated", { result.cameraEstimated ? 1.0 : 0.0 });
    addNumbers(fd, "LightingEstimated", { result.lightingEstimated ? 1.0 : 0.0 });
    addNumbers(fd, "Overlap", { result.overlap });
    addNumbers(fd, "FitPSNR", { result.fitPSNR });
    const auto& bg = result.background;
    addNumbers(fd, "Background",
      { bg.bottom[0], bg.bottom[1], bg.bottom[2], bg.top[0], bg.top[1], bg.top[2] });
    addNumbers(fd, "GradientBackground", { bg.gradient ? 1.0 : 0.0 });
    addNumbers(fd, "Orbit", { result.orbit[0], result.orbit[1], result.orbit[2] });
    addNumbers(fd, "Zoom", { result.zoom });
    addNumbers(fd, "Pan", { result.pan[0], result.pan[1] });
    addNumbers(fd, "Timings",
      { result.backgroundSeconds, result.cameraSeconds, result.fitSeconds, result.seconds });
    addFitFigures(fd, result.tf);
  };
  if (ranks)
  {
    ranks->step(describe);
    json = ranks->broadcast(json);
  }
  else
    describe();

  // before / after at the found view, and port 1: the render and the masks. The TFs as they are
  // applied: the presets (ParaView's table of their nodes); 2D: the table. Under MPI the ranks
  // render their pieces, the first composites.
  auto render = [&](const ddg::TransferFunctionFile& tf)
  { return volume.render(ranks, tf, result.view); };
  ddg::TransferFunctionFile applied;
  applied.is2D = result.tf.twoD;
  if (applied.is2D)
    applied.tf2D.table = result.tf.table2D;
  else
    applied.tf1D = ddg::parsePreset(json);
  const ddg::Image afterRGBA = render(applied);
  ddg::Image beforeRGBA;
  if (initialTF && !result.tf.twoD)
  {
    ddg::TransferFunctionFile initial;
    initial.tf1D = *initialTF;
    beforeRGBA = render(initial);
  }
  if (!first)
    return;
  // the part of the picture matched (inside a letterbox): the view and the masks are its size
  const ddg::Image rgbPicture = ddg::matchparts::cropTo(ddg::toChannels(picture, 3), result.crop);
  vtkFieldData* fd = output->GetFieldData();
  addNumbers(fd, "Crop",
    { static_cast<double>(result.crop[0]), static_cast<double>(result.crop[1]),
      static_cast<double>(result.crop[2]), static_cast<double>(result.crop[3]) });
  const ddg::Image after = overBackground(afterRGBA, result.view);
  double before = std::numeric_limits<double>::quiet_NaN();
  if (!beforeRGBA.empty())
    before = ddg::psnr(overBackground(beforeRGBA, result.view), rgbPicture, result.masks.overlay);
  addNumbers(fd, "PicturePSNR", { before, ddg::psnr(after, rgbPicture, result.masks.overlay) });
  vtkImageData* masks = vtkImageData::GetData(outputVector, 1);
  addImageArray(masks, after, "Image", 3);
  if (!result.masks.foreground.empty())
    addImageArray(masks, result.masks.foreground, "Foreground", 1);
  if (!result.masks.overlay.empty())
    addImageArray(masks, result.masks.overlay, "Overlay", 1);
  if (!this->OutputFile.empty())
    ddg::writeFileAtomic(this->OutputFile, json, "transfer function");
}

// --- another volume's picture (ddg::carryLook) ---------------------------------------------------

void vtkDDGReconstructTransferFunction::ExecuteCarryLook(
  vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector)
{
  this->Preview = nullptr;
  // under MPI every rank carries the look in step over its own piece; the first rank reads the
  // picture (the others may not see its path) and writes
  const ddg::RankGroup* ranks = this->Ranks();
  const bool first = !ranks || ranks->rank() == 0;
  // a given view's lighting (Shade and its coefficients) is the look's; nothing else of it is read
  const auto read = firstRankReads(ranks, this->TargetImageData, this->TargetImageFile,
    [&] { return ddg::lightingToJson(ddg::filterLighting(this->ViewJSON, this->ViewFile)); });
  const ddg::Image& picture = read.first;
  const std::string& lightingText = read.second;
  ddg::Lighting lighting;
  auto parse = [&] { lighting = ddg::parseLighting(lightingText, "the lighting"); };
  ranks ? ranks->step(parse) : parse();
  const PictureVolume volume(ranks, input, array, this->InputWholeExtent(), false, this);
  const ddg::DifferentiableRenderer& renderer = *volume.renderer;
  ddg::CarryLookOptions opt;
  opt.fit.snapshotEvery = this->PreviewEvery;
  opt.fit.seed = static_cast<unsigned>(this->Seed);
  opt.fit.iterations = std::min(opt.fit.iterations, this->Iterations); // its steps: XML
  opt.lighting = lighting;
  if (!this->InitialTransferFunction.empty()) // a query's design: free bins from it
    ddg::carryLookFrom(opt,
      ddg::parsePreset(this->InitialTransferFunction, "InitialTransferFunction"),
      renderer.dataRange());
  // the preview: the fit's TF at the first view, over the picture's background when it has one
  ddg::CarryLookResult previewOf;
  try
  {
    previewOf.background = ddg::estimateBackground(ddg::toChannels(picture, 3));
  }
  catch (const ddg::Error&)
  {
  }
  const ddg::View previewView = ddg::carriedLookView(renderer.bounds(), previewOf, opt, 128);
  const int steps = opt.fit.iterations;
  // with a kind check after it (a reference drawn takes seconds) the fit fills 80 % of the bar
  const double fitShare = this->KindNetwork.empty() ? 1.0 : 0.8;
  this->SetProgressText("carry");
  ddg::CarryLookResult result;
  auto carry = [&]
  {
    result = ddg::carryLook(renderer, picture, opt,
      [&](int step, double, const ddg::ReconstructionResult* snapshot)
      {
        if (snapshot) // collective under MPI: every rank renders its part
        {
          const ddg::Image shot = ddg::renderResult(renderer, *snapshot, previewView, {});
          if (first)
          {
            auto image = vtkSmartPointer<vtkImageData>::New();
            addImageArray(image, overBackground(shot, previewView), "Image", 3);
            this->Preview = image;
          }
        }
        this->UpdateProgress(fitShare * std::clamp(static_cast<double>(step) / steps, 0.0, 1.0));
        return keepGoing(this, ranks);
      });
  };
  if (ranks)
    ranks->step(carry);
  else
    carry();
  this->SetProgressText(nullptr);

  vtkTable* output = vtkTable::GetData(outputVector, 0);
  const ddg::View view = ddg::carriedLookView(renderer.bounds(), result, opt, 256);
  std::string json;
  auto describe = [&]
  {
    if (!first)
      return;
    json = writeTable(output, result.fit, volume.caster(), view,
      presetName(input, array, "carried look", this->OutputFile));
    describeCarriedLook(output->GetFieldData(), result, view);
    if (!ranks)
      ddg::addKindCheck(this, output->GetFieldData(), this->KindReferences, this->KindNetwork,
        picture, *volume.volume);
  };
  if (ranks)
  {
    ranks->step(describe);
    json = ranks->broadcast(json);
    if (!this->KindNetwork.empty()) // the fingerprint streamed once per volume
      ddg::addKindCheckOnRanks(this, output->GetFieldData(), this->KindReferences,
        this->KindNetwork, picture, *ranks, *volume.pieces,
        this->KindFingerprint->get(*ranks, *volume.pieces, input, array));
  }
  else
    describe();
  // port 1: the TF as it is applied (ParaView's table of the preset's nodes) at the view
  ddg::TransferFunctionFile applied;
  applied.tf1D = ddg::parsePreset(json);
  const ddg::Image rendered = volume.render(ranks, applied, view);
  if (!first)
    return;
  addImageArray(vtkImageData::GetData(outputVector, 1), overBackground(rendered, view), "Image", 3);
  if (!this->OutputFile.empty())
    ddg::writeFileAtomic(this->OutputFile, json, "transfer function");
}

namespace
{
void describeCarriedLook(
  vtkFieldData* fd, const ddg::CarryLookResult& result, const ddg::View& view)
{
  addString(fd, "View", ddg::viewToJson(view));
  addBackground(fd, view);
  auto regions = vtkSmartPointer<vtkDoubleArray>::New();
  regions->SetName("Regions");
  regions->SetNumberOfComponents(6);
  for (const auto& r : result.regions)
  {
    const double row[6] = { r.region.lo, r.region.hi, r.colour[0], r.colour[1], r.colour[2],
      r.share };
    regions->InsertNextTuple(row);
  }
  fd->AddArray(regions);
  addNumbers(fd, "ColourDistance", { result.distanceStart, result.distanceEnd });
  addNumbers(fd, "ShapeAgreement", { result.shapeAgreement, result.shapesAgree ? 1.0 : 0.0 });
  addNumbers(fd, "OverlayShare", { result.overlayShare });
  addNumbers(fd, "Timings", { result.seconds });
  addFitFigures(fd, result.fit);
}
} // namespace
