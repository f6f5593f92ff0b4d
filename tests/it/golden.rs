//! Frames that must not change: the SHA-256 of every file of a fixed set of renders, recorded
//! before the restructure of issue 25 ("one direction through the renderer"). A change that
//! moves code around must leave every frame, AOV and count bit for bit as it was; a change
//! that means to alter the pixels updates the table below on purpose (the failure prints the
//! whole new table). Updated once on purpose since: when every transcendental function on the
//! output path moved from the host's C library to the pure-Rust `libm` (issue 20, item 10),
//! which changed last bits (the bunny's frame 0 at 320×240: 306 of 7.77 M queries flipped).
//! Since then these hashes hold on any host whatever its C library.

use crate::common;

use std::path::Path;

use sha2::{Digest, Sha256};

/// One render through the binary: a name, the spec (relative to the repository) and its flags.
struct Render {
    name: &'static str,
    spec: &'static str,
    flags: Vec<String>,
}

/// The bunny at a quarter of its size: what every method is checked on.
const BUNNY: &str = "anims/bunny-turntable.toml";
const SMALL: &str = "--width 320 --height 240";

fn render(name: &'static str, spec: &'static str, flags: &str) -> Render {
    Render {
        name,
        spec,
        flags: flags.split_whitespace().map(String::from).collect(),
    }
}

fn renders() -> Vec<Render> {
    let mut v = vec![
        // The default animation's first frames at one sample per pixel, as the README's
        // first command rendered them before samples per pixel; then at four samples, as it
        // renders them now (recorded when samples per pixel came).
        render(
            "shapes-turntable",
            "anims/shapes-turntable.toml",
            "--frames 0..3 --spp 1",
        ),
        render(
            "shapes-turntable-spp4",
            "anims/shapes-turntable.toml",
            "--frames 0..2 --spp 4",
        ),
    ];
    for (name, method) in [
        ("bunny-none", "none"),
        ("bunny-brute", "brute"),
        ("bunny-scan-warp-boundary", "scan-warp-boundary"),
        ("bunny-grid-warp-boundary", "grid-warp-boundary"),
        ("bunny-grid-nowarp-boundary", "grid-nowarp-boundary"),
        ("bunny-grid-warp-uncertainty", "grid-warp-uncertainty"),
        ("bunny-grid-nowarp-uncertainty", "grid-nowarp-uncertainty"),
        // Added after the restructure (its first method beyond the paper's).
        ("bunny-scan-nowarp-uncertainty", "scan-nowarp-uncertainty"),
    ] {
        let flags = format!("{SMALL} --frames 0..2 --method {method}");
        v.push(render(name, BUNNY, &flags));
    }
    for (name, flags) in [
        (
            "bunny-nowarp-all",
            "--frames 0..2 --method grid-nowarp-uncertainty --flood-to all",
        ),
        (
            "bunny-nowarp-contrary",
            "--frames 0..2 --method grid-nowarp-uncertainty --flood-to contrary",
        ),
        (
            "bunny-warp-contrary",
            "--frames 0..2 --method grid-warp-uncertainty --flood-to contrary",
        ),
        (
            "bunny-tuned",
            "--frames 1 --h0 8 --min-voters 2 --lights 100 --tile 24",
        ),
        (
            "bunny-scan-block",
            "--frames 1 --method scan-warp-boundary --scan-block 32 --tile 48",
        ),
        ("bunny-validate", "--frames 0..2 --validate"),
        (
            "bunny-validate-warp",
            "--frames 1 --validate --method grid-warp-boundary",
        ),
        (
            "bunny-validate-scan",
            "--frames 1 --validate --method scan-warp-boundary",
        ),
        // Orbit: reprojection. Frames 2..6 start mid-chain, so frames 0 and 1 warm it up.
        (
            "bunny-temporal-orbit",
            "--frames 2..6 --temporal --keyframe 4 --validate",
        ),
        (
            "bunny-temporal-warp",
            "--frames 0..3 --temporal --method grid-warp-uncertainty",
        ),
    ] {
        v.push(render(name, BUNNY, &format!("{SMALL} {flags}")));
    }
    // Lambertian materials keep the bits they had before glTF materials: the bunny with
    // --lambert against bunny-brute's hashes as recorded before materials (its materials,
    // metallic 0 and roughness 1, have had specular since).
    v.push(render(
        "bunny-brute-lambert",
        BUNNY,
        &format!("{SMALL} --frames 0..2 --method brute --lambert"),
    ));
    // Spin: votes pulled through the turn, light-space edges.
    v.push(render(
        "bunny-temporal-spin",
        "anims/bunny-spin.toml",
        &format!("{SMALL} --frames 0..4 --temporal --validate"),
    ));
    v
}

/// The recorded hashes: one line per file, `render file sha256`. `stats.csv` is hashed
/// without its `seconds` column, which is a wall-clock time, and without the `spp` column
/// added after most were recorded (checked to be the render's own).
const EXPECTED: &str = "\
shapes-turntable frame_0000.exr cd044230fab30debeec8944b689b07cbf761274e62d54994ec352d2b120b5a0d
shapes-turntable frame_0000.png 1cbe80db6928cae6252c151ea368e81d6681f0c4d710b4b90db1cfc4bd2a63a3
shapes-turntable frame_0001.exr 13696c7b7dc24c743d47fd8d91671e626092d595c58e9e3e4238742c6a00eaa9
shapes-turntable frame_0001.png 640aaba349e431b8cf26e7b8dfa99be725775606f25c06aa7cc4c1aa3581343b
shapes-turntable frame_0002.exr 5ace5a9bfcb9945d8cecc1c63ef72cf9eb7df730e6d935bc3ed91c889c9a1699
shapes-turntable frame_0002.png 7782ce016d8711a540b0bc783d6b6f9d7122a4e38cd79b66c234b9510a0028dc
shapes-turntable lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable stats.csv 6c9bf6a07586f6cb955257924cb9255647d18f46190f5d7fed02b99bf10bcb70
shapes-turntable-spp4 frame_0000.exr 935f17a5e3847bcc431c6027da7d1286fd89a3dc83c3866cfe8d585c5de31e73
shapes-turntable-spp4 frame_0000.png f2260c5b38912a03fb88474b1d51e8eb32b021de6d2136e99e0214a886eace13
shapes-turntable-spp4 frame_0001.exr dca6131a88291bd4ffe567e15afcfeaab8ef679f17440ce94efd06afb9c64b8c
shapes-turntable-spp4 frame_0001.png 9b76d7ca74a34dae4b0dc7c272520cd306f37624b45bfed726758bdbb6ce7293
shapes-turntable-spp4 lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable-spp4 stats.csv 540850352825ebd026f88ab680b5861a893a3a7aa24461a346619bfeaaca3a45
bunny-none frame_0000.exr ab41629fd85034bef4571bd436402fd1e0a4c976d3525d9c73c6deb3aef8d9eb
bunny-none frame_0000.png aa0eef2241793907cb23849ed88b5a865c5d91e0d0afcdc7d5d4463351679993
bunny-none frame_0001.exr 1da260dbf20d41d5f8af110713e1917f5a4c430412161342b329e39819f00e7d
bunny-none frame_0001.png 69fb927b5716d8f2547425875e2d527408ec04a8eee1e4eb8acde0ace4784a1a
bunny-none lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-none stats.csv f2da642e694712dbcb867dfec49916da8b09cfe3fe737ebc55d3bea2ad9bec4b
bunny-brute frame_0000.exr 1a66e8f817d259b26385e771eea9595def3f339c302798db9a20e0c8e9c89658
bunny-brute frame_0000.png 38ab726c7a051e7b217cc7dc6128bf9bf10de3d4fe56a5151ddede1affef1b2b
bunny-brute frame_0001.exr 733e7dbda04473ce0a54b4c6b892241bd1cacabb11e3a909656bfe7bf689d4f0
bunny-brute frame_0001.png 00ca72651904f1a277017363da8265f9a72af1d9c6feb3177762b676aa991bc6
bunny-brute lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute stats.csv dea59863af088772662dec0ee729feb3124e433f2c3d7e51e43b4e88de4d2b02
bunny-brute-lambert frame_0000.exr 1a66e8f817d259b26385e771eea9595def3f339c302798db9a20e0c8e9c89658
bunny-brute-lambert frame_0000.png 38ab726c7a051e7b217cc7dc6128bf9bf10de3d4fe56a5151ddede1affef1b2b
bunny-brute-lambert frame_0001.exr 733e7dbda04473ce0a54b4c6b892241bd1cacabb11e3a909656bfe7bf689d4f0
bunny-brute-lambert frame_0001.png 00ca72651904f1a277017363da8265f9a72af1d9c6feb3177762b676aa991bc6
bunny-brute-lambert lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute-lambert stats.csv dea59863af088772662dec0ee729feb3124e433f2c3d7e51e43b4e88de4d2b02
bunny-scan-warp-boundary frame_0000.exr ebae30733cb008f3d53fc243f648186ab098679c9808d35c719139ffe5552ae0
bunny-scan-warp-boundary frame_0000.png d0246a493cd874e2a9015f2fe265b36d823f3c860d3f5a0f8bfba2b2187ba5dd
bunny-scan-warp-boundary frame_0001.exr 3eb585e53051746d26276962eb05533d6a57e7c2318cebfeda2b152d0c72ca76
bunny-scan-warp-boundary frame_0001.png 7e13179f69013b0bfc2372e6fa2f81f52bf94af70337f1f784017e5a49e27963
bunny-scan-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-warp-boundary stats.csv 85e705dda9d8539aa40b2a17d9a47a05a5a4ec9f34ec6e2355389ed3bbabe315
bunny-grid-warp-boundary frame_0000.exr ad118b670c4972bc5e3ea449282e0fc1d2fa7172a1877c022ef3dcffc3dcaebb
bunny-grid-warp-boundary frame_0000.png 841c549e6d947f704333c9e81c40ff2e4fd43382e316a7c9e7f3a9ddd8b28c49
bunny-grid-warp-boundary frame_0001.exr 271614a34e1fffc15a8b59cfb35830957285f5738d1bfd3e58eeb5b243519ce8
bunny-grid-warp-boundary frame_0001.png 3e43e502e26f5ad61b732f0e827406a5a02cc258ccc5401c3cb4b4e667ac918c
bunny-grid-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-boundary stats.csv cf291ceba167064918e92c442f0967c92cdb60bf701abcf7eb4e407ce521528a
bunny-grid-nowarp-boundary frame_0000.exr ac5d83d235076e223235a9e997a3ae3f8d3e13629e6e78be4bc9d8990769ce00
bunny-grid-nowarp-boundary frame_0000.png 665d54f49d2271139880f269529819797c5b892f274cebdded169ab38158a637
bunny-grid-nowarp-boundary frame_0001.exr 0eccccff90fac1433dd6a378a9153a4ebdece0c9869a03d3d290dca0f08cd097
bunny-grid-nowarp-boundary frame_0001.png d3e691344543826ae9ac6e2ea5a43019a61c764302e9587ee339e5b3c63a540c
bunny-grid-nowarp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-boundary stats.csv 50ce3e753a666cfca057a41e1eac6b746e4c0121c152def0b0e6bc0c21f30da7
bunny-grid-warp-uncertainty frame_0000.exr ab7cc8d779fa807cd6ac253543330537c627aa8aeef57f6212d3aabc6b13e44e
bunny-grid-warp-uncertainty frame_0000.png 31fe19fcbf3fad7e3709e0136735bd5647df88dec5e29d61ac425b1bbde58b20
bunny-grid-warp-uncertainty frame_0001.exr eb61cb145c5a75431da670f536d8289010704264c5a1f817e92f37be50f7fbb3
bunny-grid-warp-uncertainty frame_0001.png 7a6bf4eec448091931140f0cbb3cbef3f8e0f602a68258f0a314b92efd89ef98
bunny-grid-warp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-uncertainty stats.csv d204b31c9e78552d93afb35da486084fdf321244707d9259bb57391bbc29479e
bunny-grid-nowarp-uncertainty frame_0000.exr bd861b7ccf31b5f06856020b37bae599e50ad4e3ba2f60dc14c1de7f7a26afca
bunny-grid-nowarp-uncertainty frame_0000.png c7e8621b29e62c2023ba6ae210f791ecc66488303e8da423d615e2b8db3b2f78
bunny-grid-nowarp-uncertainty frame_0001.exr 3c4d392635e4e710a12959463a1df6249f3c065c103c792d991d895dbf9efa17
bunny-grid-nowarp-uncertainty frame_0001.png 1040257b95eb1a33f32a930de5f269d40dd1ec4019a099db4c3e5c136c35d2b3
bunny-grid-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-uncertainty stats.csv 52dcc6b93f0df6759dc69301f316556989c104c376de0989b394ee999ec2801e
bunny-scan-nowarp-uncertainty frame_0000.exr 23e4688329085e385446aa9e82e0d5faeb421f3bd58ac00d45a687358268d34a
bunny-scan-nowarp-uncertainty frame_0000.png 08c3aa47c7077557c89c342e3ca2d6943e676fa18d06e76fc1d4ffd4408b9a57
bunny-scan-nowarp-uncertainty frame_0001.exr ebe4721974b09111b9789c10bfc5bb3fc6dee6d81517acbfb0da7aadbddcfe79
bunny-scan-nowarp-uncertainty frame_0001.png 973e878dc2dfcde0d39ac565c6893c9264d397b130d35c18da9bafc3f95d7937
bunny-scan-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-nowarp-uncertainty stats.csv b23b55384c5c4f8318636ee5cd7281cf1fdb7ae0aae4bbff66bd2cf0928c8aa9
bunny-nowarp-all frame_0000.exr c0c11aea5b687ad3afa19e6490550c55138778f8b5be9b5235776bce96650430
bunny-nowarp-all frame_0000.png 96103b23cf51625e1125775c1db90631dd638cdebdb760250ebd08f33b0ae17a
bunny-nowarp-all frame_0001.exr cf6df18e7128bb8f20be8baf476872d7b8e7f1d080c49ace44a2781a5203ae9a
bunny-nowarp-all frame_0001.png 0785ef97a9b1020669935c4617e56672b1f8c52ce2e08bd3a372cdb7457e37d0
bunny-nowarp-all lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-all stats.csv c35dbd5906f633061660959526fd7e00ddd26c47b7440d557fc9cc0240f7d76e
bunny-nowarp-contrary frame_0000.exr 2c3e707fe89720770953e71eeaa65c78abee0137675a43682c8abb5534c9eefc
bunny-nowarp-contrary frame_0000.png 8b07e090db92a9809d3ae88e9926116cd9ad9dcbe185f9ff9eb42587c704e897
bunny-nowarp-contrary frame_0001.exr 02e39fdc454b26aafb8c65cde0bc4b3601883f9dcea5d7765dbcce2d190374c9
bunny-nowarp-contrary frame_0001.png c261f431051ae5968cdd8f0294c83a05aa506e31c8f57c3ea4e9a723094282d7
bunny-nowarp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-contrary stats.csv 68d99b20ceb44db79e87162568af23ee9af87e41026a427be6a13feb96ad0395
bunny-warp-contrary frame_0000.exr b4d42a4e739299b5855a94e6cf0a8bf3955c1a8706ae1284622ff861636e75e3
bunny-warp-contrary frame_0000.png 1275dc70254273933f8b4df80c011feb8f930685a0dd1ec812c00f0f5487213a
bunny-warp-contrary frame_0001.exr 6b65f7a9afd94df64a7eb4c6c0cb0f5cc6aa053558de5edf1ceea490adecb165
bunny-warp-contrary frame_0001.png f4da0a518d258bd3d37683f204c3b90f5cbc468e795fd20e9f172372378353f6
bunny-warp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-warp-contrary stats.csv 6a80d3d5122f34b66f6d1c0a198f92c5d4d97e296a99ec8d2a70bb147d51406b
bunny-tuned frame_0001.exr 0e6c55696d297e2d552c9d54df6f75f3b671396bda39921ff719a5247e4f21b0
bunny-tuned frame_0001.png f6658ec6b7460d62c83691d59c83be22d1533171c3e158604069a37db8bf56cb
bunny-tuned lights.json f7dd94f909deb0f100b9dbfd34fb72d29f04f800af100ca2098df3f30729369f
bunny-tuned stats.csv 2722223dd2135845d95cc8878a62403f7f49961127b19f511b00e56a0cb0792f
bunny-scan-block frame_0001.exr d87eb4469d10107fb064b966d9d13eed691a15970ba81dbd5a84b09ce8f2a89b
bunny-scan-block frame_0001.png 0f868d30a3dd7e041c885eb57dffb459c632b879a7c20e2f14cfd700093398b4
bunny-scan-block lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-block stats.csv 894fdcd38d971118b4fc635b79a56626e20f72f00a72d065dee8f05017b2d58b
bunny-validate frame_0000.exr 187048d6b39e3d8a1990d6cae10a3f04a8314c6f1bd25a8f50fb3406a6721d3a
bunny-validate frame_0000.png c7e8621b29e62c2023ba6ae210f791ecc66488303e8da423d615e2b8db3b2f78
bunny-validate frame_0001.exr d8adae784606720c5d6393558fc07fc705ac53727834e1ab3603d569d48bca1d
bunny-validate frame_0001.png 1040257b95eb1a33f32a930de5f269d40dd1ec4019a099db4c3e5c136c35d2b3
bunny-validate lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate stats.csv f2ce11864d6675204fbe9a2205a65ff3104deb4df3bfc0601c3927f4b55069e5
bunny-validate-warp frame_0001.exr 2cfbcdf62c13fcef75795aa4d62415ac196d28217f69a62ab3ec6861b56dfbeb
bunny-validate-warp frame_0001.png 3e43e502e26f5ad61b732f0e827406a5a02cc258ccc5401c3cb4b4e667ac918c
bunny-validate-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-warp stats.csv 13192e9e125a58edc6c74aa1f46fbf4f1250a8fc5be3570c303ba9779234b2be
bunny-validate-scan frame_0001.exr 88fe303c9330548703f0777edbadd3ede39e7e291d468021afee76ad1b8b851e
bunny-validate-scan frame_0001.png 7e13179f69013b0bfc2372e6fa2f81f52bf94af70337f1f784017e5a49e27963
bunny-validate-scan lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-scan stats.csv 31b9cc7372f274334cd2c92ce6fc71482412138e8248c26ee87a5e5c0666831a
bunny-temporal-orbit frame_0002.exr 676e4a8d2f8eeb5a75edc76e8e3221bafee30b53486dcc6eafe07d47728a59da
bunny-temporal-orbit frame_0002.png d384e257e000fb0342d632899b0a0de2925de4af71a273807f39e9b0e42af9bb
bunny-temporal-orbit frame_0003.exr 0409d5f89cc4536320e5d4160c8e9a6cfc50898bd1b757d0f5f3ab8874497bd2
bunny-temporal-orbit frame_0003.png fdcd7730593cff47522760f837aeae6f16d87a7d4a28a66286aebaec69208260
bunny-temporal-orbit frame_0004.exr 1822d5a130094d84b907398046e9a82edd1a9499cd05ffec54dbd89f768aa903
bunny-temporal-orbit frame_0004.png 4964d9000e91c1d5b05dc0645228599be680e4fdc7b1f8c7c8b46798aaf722ea
bunny-temporal-orbit frame_0005.exr 1b81d49e5d96eb25a383538e05357279971f32f17e5e05707edbad399e274dc5
bunny-temporal-orbit frame_0005.png cdbc624f13cca2731c96345767686fa49654c0beba90c33a88cd316d6fc7429b
bunny-temporal-orbit lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-orbit stats.csv b83578beb861c2e98b9202a7d2038b39153e0ea3193d1305eec75fbf7153dc14
bunny-temporal-warp frame_0000.exr ab7cc8d779fa807cd6ac253543330537c627aa8aeef57f6212d3aabc6b13e44e
bunny-temporal-warp frame_0000.png 31fe19fcbf3fad7e3709e0136735bd5647df88dec5e29d61ac425b1bbde58b20
bunny-temporal-warp frame_0001.exr e73ffb2e974886c05a0f5e7a1de0afc03f02eb0dbd564c2a6a5b00826fcc076e
bunny-temporal-warp frame_0001.png e04a5965a94e3142dc6eaf934f21bf5079aa5e0231a3338490d588bda91eaec2
bunny-temporal-warp frame_0002.exr de938ab48d3570587671695c7fc6cc635338b48f71566c91a92de71ce423f23f
bunny-temporal-warp frame_0002.png 2988a01f4beb8e7a6cb94d053a57591b002b863fd5b5d55ab5fa22a336649116
bunny-temporal-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-warp stats.csv 5ec83275df1b4d20ac5e883b5d27caf1c1b80db1cb4ef9b89c5f41b980fd39a0
bunny-temporal-spin frame_0000.exr 7d8d0fa8d094deae2c3c31ef1b99d2d7dc3d9cd316128b7de3ef9a809f010469
bunny-temporal-spin frame_0000.png 96d2340bd0cb3f0cbdd683157c72414f6684f8674e9b7aa05395fe86597820ea
bunny-temporal-spin frame_0001.exr a3c8e3797435237f1b60fe528aa4c505db7775e120422a61ed7f464aa1e3ca21
bunny-temporal-spin frame_0001.png 0062c776ea2d435844cd5a5d9f444c39fd062c42ce40af9b55cd7fdfc8760ae4
bunny-temporal-spin frame_0002.exr 85426cfe103b2d00f51e6b9649449836b704e125c989613f47613c09c6db8614
bunny-temporal-spin frame_0002.png f0fe1affe0248707c8ffa039adae94acd2cd4f064f919b62bd34ffacd2634f42
bunny-temporal-spin frame_0003.exr 385663743baff9a5d1b7a6528d03dd1460d38a9422f423ab4052b6522ff30258
bunny-temporal-spin frame_0003.png 10125a9187fec8dd73438cfb4ed8f8c81099fcec1bd52331bb3c4da3a8971a11
bunny-temporal-spin lights.json 103f720aa426b7ad9ed05f0b47b0a7d9096a5429b996d950aa4e62c981aa7cd5
bunny-temporal-spin stats.csv 182f1457ae78d5034ac30df083ab6116e1a54230523ac1cdeb93df63154cd420
";

fn sha(bytes: &[u8]) -> String {
    format!("{:x}", Sha256::digest(bytes))
}

/// `stats.csv` with the `seconds` column emptied and the last column, `spp`, removed once
/// checked to be `spp` everywhere.
fn stats_without_seconds(text: &str, spp: &str) -> String {
    let mut lines = text.lines();
    let mut header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == "seconds")
        .expect("stats.csv has a seconds column");
    assert_eq!(
        header.pop(),
        Some("spp"),
        "stats.csv ends with the spp column"
    );
    let mut out = format!("{}\n", header.join(","));
    for line in lines {
        let mut f: Vec<&str> = line.split(',').collect();
        f[col] = "";
        assert_eq!(f.pop(), Some(spp), "a golden render at {spp} spp: {line}");
        out.push_str(&f.join(","));
        out.push('\n');
    }
    out
}

/// The output files of one render folder (frames, lights, stats), hashed, in name order.
/// `lights.json` names the map it came from: the assets folder is hashed as `ASSETS`, so the
/// hashes do not depend on where the repository and its assets are. The bookkeeping for
/// `--resume` (`settings.txt`, `records/`) is not output.
fn hashes(dir: &Path, assets: &str, spp: &str) -> Vec<(String, String)> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "settings.txt" && dir.join(n).is_file())
        .collect();
    names.sort();
    names
        .into_iter()
        .map(|n| {
            let bytes = std::fs::read(dir.join(&n)).unwrap();
            let h = if n == "stats.csv" {
                sha(stats_without_seconds(&String::from_utf8(bytes).unwrap(), spp).as_bytes())
            } else if n == "lights.json" {
                sha(String::from_utf8(bytes)
                    .unwrap()
                    .replace(assets, "ASSETS/")
                    .as_bytes())
            } else {
                sha(&bytes)
            };
            (n, h)
        })
        .collect()
}

#[test]
fn every_recorded_frame_keeps_its_bits() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let tmp = tempfile::tempdir().unwrap();
    let assets = common::assets_dir();
    let mut got: Vec<(String, String, String)> = Vec::new();
    for r in renders() {
        let out = tmp.path().join(r.name);
        // The specs name their files under ../assets; point them at the test assets.
        let text = std::fs::read_to_string(root.join(r.spec)).unwrap();
        let spec = tmp.path().join(format!("{}.toml", r.name));
        let dir = format!("{}/", assets.display());
        std::fs::write(&spec, text.replace("../assets/", &dir)).unwrap();
        let o = common::bin()
            .args(["render", "-q", "--no-report"])
            .arg(&spec)
            .args(&r.flags)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{}: {}",
            r.name,
            String::from_utf8_lossy(&o.stderr)
        );
        let spp = r
            .flags
            .iter()
            .position(|f| f == "--spp")
            .map_or("1", |k| r.flags[k + 1].as_str());
        for (file, h) in hashes(&out, &dir, spp) {
            got.push((r.name.to_string(), file, h));
        }
    }
    let table: String = got
        .iter()
        .map(|(r, f, h)| format!("{r} {f} {h}\n"))
        .collect();
    let expected: Vec<(String, String, String)> = EXPECTED
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(' ').collect();
            (f[0].to_string(), f[1].to_string(), f[2].to_string())
        })
        .collect();
    let changed: Vec<String> = got
        .iter()
        .filter(|g| !expected.contains(g))
        .map(|(r, f, _)| format!("{r}/{f}"))
        .chain(
            expected
                .iter()
                .filter(|e| !got.iter().any(|g| g.0 == e.0 && g.1 == e.1))
                .map(|(r, f, _)| format!("{r}/{f} (missing)")),
        )
        .collect();
    assert!(
        changed.is_empty(),
        "{} file(s) changed: {}\nthe new table:\n{table}",
        changed.len(),
        changed.join(", ")
    );
}
