"""params.yaml `pacer`: parameters of the pacer track (PACER, Mao et al. RA-L 2025)."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from navlab.core.params.fields import between, section


@section
class PacerLayoutParams:
    """Procedural label layouts of one BEV image: warped Voronoi regions plus an optional trail band."""

    regions: Annotated[tuple[int, ...], between(1, 8, length=2)]  # [min, max] Voronoi regions
    path_probability: Annotated[float, between(0.0, 1.0)]  # chance of a trail band of one more terrain
    path_width: Annotated[tuple[float, ...], between(0.01, 1.0, length=2)]  # trail width / image size
    boundary_warp: Annotated[float, between(0.0, 1.0)]  # region-boundary wobble / image size
    # chance a training item is instead a window of a SuReNav train/val map (street network: thin sidewalks
    # and strips, 2-4 terrains per window), the layouts the evaluation maps are cut from (issue 24)
    street_windows: Annotated[float, between(0.0, 1.0)]
    # pixels per SuReNav map pixel (metre) of every street layout (aerial maps, map windows, street windows):
    # at 1 a 2 m sidewalk is 2 px of texture, too thin to recognise (issue 24)
    street_zoom: Annotated[int, between(1, 8)]


@section
class PacerPhotometricParams:
    """Lighting and sensor effects added on top of the texture fill."""

    brightness: Annotated[float, between(0.0, 1.0)]  # global gain jitter, +-
    gradient: Annotated[float, between(0.0, 1.0)]  # linear lighting ramp across the image, +-
    shadows: Annotated[int, between(0)]  # at most this many soft shadows
    shadow_strength: Annotated[float, between(0.0, 1.0)]  # darkest shadow multiplies by 1 - this
    noise_std: Annotated[float, between(0.0, 1.0)]  # per-pixel Gaussian noise


@section
class PacerRecolourParams:
    """D_synthetic's recoloured terrains (navlab.pacer.recolour): new colours for each terrain, alike in image
    and context, so that texture, not a photograph's colour, ties a context patch to its terrain (issue 24)."""

    probability: Annotated[float, between(0.0, 1.0)]  # chance each terrain of a D_synthetic item is recoloured
    grey: Annotated[float, between(0.0, 1.0)]  # chance a recoloured terrain turns grey (saturation 0)
    saturation: Annotated[tuple[float, ...], between(0.0, 4.0, length=2)]  # [low, high] chroma scale otherwise


@section
class PacerCameraParams:
    """The ground-plane homography: BEV -> forward camera -> BEV, losing detail far from the robot."""

    near_width: Annotated[float, between(0.05, 1.0)]  # bottom (near) edge of the FOV trapezoid / image width
    resolution: Annotated[float, between(0.1, 4.0)]  # camera image width / BEV width
    aspect: Annotated[float, between(0.1, 4.0)]  # camera image height / camera image width


@section
class PacerSizesParams:
    train: Annotated[int, between(1)]
    val: Annotated[int, between(1)]
    test: Annotated[int, between(1)]


@section
class PacerAerialParams:
    """Large rendered aerial maps for the navigation tables (no FOV mask)."""

    size: Annotated[int, between(32)]  # pixels per side
    maps: Annotated[int, between(1)]  # maps per evaluation set
    regions: Annotated[tuple[int, ...], between(2, 64, length=2)]
    terrains: Annotated[tuple[int, ...], between(2, 16, length=2)]  # distinct terrains per map
    paths: Annotated[tuple[int, ...], between(0, 8, length=2)]  # trails across the map
    layout: Literal["procedural", "surenav"]  # Voronoi regions + trails, or windows of SuReNav test maps


@section
class PacerDataParams:
    """Terrain banks, BEV rendering, preference contexts and dataset sizes (navlab.pacer data half)."""

    seen: dict[str, tuple[str, ...]]  # terrain class -> photographs under data/raw/terrain
    unseen: dict[str, tuple[str, ...]]
    synthetic: dict[str, tuple[str, ...]]
    realistic_ordering: tuple[str, ...]  # seen + unseen classes, most preferred first
    context_fraction: Annotated[float, between(0.05, 0.5)]
    image_size: Annotated[int, between(16)]
    patch_size: Annotated[int, between(4)]
    n_pairs: Annotated[int, between(1)]
    train_context: Literal["in_view", "superset"]  # how training contexts are drawn (superset: as deployed)
    context_extra: Annotated[int, between(0, 8)]  # superset contexts: terrains beyond those in view
    train_target: Literal["in_view", "context"]  # what a target ranks (see pacer.datasets)
    footprint_texels: Annotated[tuple[float, ...], between(8.0, 4096.0, length=2)]
    synthetic_replace: Annotated[float, between(0.0, 1.0)]
    recolour: PacerRecolourParams
    layout: PacerLayoutParams
    photometric: PacerPhotometricParams
    camera: PacerCameraParams
    sizes: PacerSizesParams
    aerial: PacerAerialParams


@section
class PacerModelParams:
    """The costmap network (pacer/model.py): a U-Net over the BEV image, a context encoder, a fusion."""

    image_channels: Annotated[tuple[int, ...], between(1), Field(min_length=1)]  # U-Net encoder widths, one max-pool after each
    bottleneck_channels: Annotated[int, between(1)]
    context_encoder: Literal["cnn", "resnet50"]
    context_channels: Annotated[tuple[int, ...], between(1)]  # widths of the small CNN (unused by resnet50)
    context_dim: Annotated[int, between(1)]  # the preference embedding
    fusion: Literal["film", "concat_mlp"]  # film: every decoder stage; concat_mlp: the released code's
    match_channels: Annotated[tuple[int, ...], between(1)]  # texture tower matching image to context patches; [] = none
    # the tower keeps full resolution (dilations 1, 2, 4, ...) instead of pooling 2 x 2 per stage (issue 24: a
    # pooled tower mixes a 1-3 px sidewalk's features with its neighbours')
    match_dilated: bool
    # a second, colour-blind tower beside the colour one, features concatenated (issue 24: the colour tower
    # loses unseen terrains that share a colour and differ in texture)
    match_luminance: bool
    # where the matcher's texture features come from (issue 61): imagenet, EfficientNet-Lite0's frozen ImageNet
    # features (strides 4 and 8) and a trained 1 x 1 projection (match_channels then only switches the matcher on);
    # scratch, the towers above trained from the seen terrains' photographs alone (a labelled variant)
    match_features: Literal["imagenet", "scratch"]


@section
class PacerPhaseEpochs:
    phase1: Annotated[int, between(1)]  # D_real
    phase2: Annotated[int, between(1)]  # D_real + D_shuffled
    phase3: Annotated[int, between(1)]  # D_real + D_shuffled + D_synthetic


@section
class PacerTrainParams:
    device: Literal["cpu", "cuda"]  # cuda where torch sees no GPU is one clear error, never a silent CPU run
    epochs: PacerPhaseEpochs  # the most epochs per phase; early stopping may end a phase sooner
    examples_per_epoch: Annotated[int, between(1)]  # drawn uniformly over the phase's datasets (Sec. V-C)
    val_examples: Annotated[int, between(1)]  # first items of each of the phase's validation sets, per epoch
    batch_size: Annotated[int, between(1)]
    lr: Annotated[float, between(1e-7, 1.0)]  # initial learning rate, decayed by a cosine over the phase's epochs
    lr_final_fraction: Annotated[float, between(0.0, 1.0)]  # the cosine ends at lr * this
    patience: Annotated[int, between(1)]  # stop a phase after this many epochs without a lower validation loss
    threads: Annotated[int, between(1, 64)]  # torch CPU threads; 1 on shared machines (oversubscription stalls)
    workers: Annotated[int, between(0, 64)]  # DataLoader processes rendering training items (0: in the main process)
    # what keeps a phase's best weights: map_windows (pixel-pair AUC on validation windows of training-geography
    # street maps, the loss breaking ties; tracks navigation, issue 24) or val_loss (the validation loss alone)
    select_on: Literal["map_windows", "val_loss"]
    select_windows: Annotated[int, between(1)]  # validation map windows scored after every epoch (map_windows)
    # weight of the matcher's matching loss beside Eq. 3 (pacer.loss.matching_loss); 0: Eq. 3 alone (as the paper)
    match_loss_weight: Annotated[float, between(0.0)]
    # weight of the terrain-contrast hinge beside Eq. 3 (pacer.loss.contrast_loss, issue 24 item 4); 0: Eq. 3 alone
    contrast_loss_weight: Annotated[float, between(0.0)]
    contrast_margin: Annotated[float, between(0.0, 1.0)]  # terrains sit >= this x their target cost gap apart


@section
class PacerSterlingParams:
    embed_dim: Annotated[int, between(2)]
    channels: Annotated[tuple[int, ...], between(1)]
    epochs: Annotated[int, between(1)]
    patches_per_epoch: Annotated[int, between(2)]
    batch_size: Annotated[int, between(2)]
    lr: Annotated[float, between(1e-7, 1.0)]
    vicreg_weights: Annotated[tuple[float, ...], between(0.0, length=3)]  # invariance, variance, covariance
    utility_steps: Annotated[int, between(1)]  # gradient steps fitting the utility to one context's pairs


@section
class PacerClassifierParams:
    channels: Annotated[tuple[int, ...], between(1)]
    epochs: Annotated[int, between(1)]
    patches_per_epoch: Annotated[int, between(1)]  # fresh patches every epoch
    val_patches: Annotated[int, between(1)]  # held-out patches (validation images) choosing the best epoch
    batch_size: Annotated[int, between(1)]
    lr: Annotated[float, between(1e-7, 1.0)]


@section
class PacerBaselineParams:
    patch_size: Annotated[int, between(4)]  # side of the square patches both baselines score
    sterling: PacerSterlingParams
    classifier: PacerClassifierParams


@section
class PacerEvalParams:
    heldout_examples: Annotated[int, between(1)]  # per evaluation set
    margin_points: Annotated[int, between(2)]  # points sampled per costmap for the margin ranking error
    cost_scale: Annotated[float, between(0.0)]  # A* cost per metre = 1 + cost_scale * predicted cost
    queries_per_map: Annotated[int, between(1)]  # the map's own start-goal pair plus extra crossings


@section
class PacerVariantParams:
    """Rows beside the main model (pacer/variants.py, issue 61)."""

    seeds: Annotated[tuple[int, ...], between(0)]  # more training seeds of the main recipe (pacer.seed is the first)


@section
class PacerParams:
    seed: Annotated[int, between(0)]
    data: PacerDataParams
    model: PacerModelParams
    train: PacerTrainParams
    baselines: PacerBaselineParams
    evaluation: PacerEvalParams
    variants: PacerVariantParams
