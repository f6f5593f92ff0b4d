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
    // Spin: votes pulled through the turn, light-space edges.
    v.push(render(
        "bunny-temporal-spin",
        "anims/bunny-spin.toml",
        &format!("{SMALL} --frames 0..4 --temporal --validate"),
    ));
    v
}

/// The recorded hashes: one line per file, `render file sha256`. `stats.csv` is hashed
/// without its `thread_seconds` column, which is a timing, and without the `spp` column
/// added after most were recorded (checked to be the render's own).
const EXPECTED: &str = "\
shapes-turntable frame_0000.exr 46249b912e7f567faa2d5b6839a432d9c3dd51201c34c0ee1fb6aefb67fbb704
shapes-turntable frame_0000.png 97c349a3f0cc7239cf6830be71accec4d243966e545672b0442d54c795b7fe23
shapes-turntable frame_0001.exr 5d64ccdec0ce8099d65520d5d2f703af07dbdc8b91a21f2be6e78d91c524c79d
shapes-turntable frame_0001.png 4f6d0ad454c0a4c6cca19ad1191c84c5e5bb04f7657e4c11862feaca8ccae638
shapes-turntable frame_0002.exr 7da838981cf0def903c5b7796a95edd23da2acb328a57795e5f236751d8f3c63
shapes-turntable frame_0002.png c210430884e8a9daf1d201b0afeebf44290ebc71076d31c66a95cb670658dec8
shapes-turntable lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable stats.csv 929046d1f0054ae7c0646953a0dee27fdd9847a44b15954f949cbea29bdc0c6a
shapes-turntable-spp4 frame_0000.exr f6a0ebe0b1920586c2d988184fc4c04ad94d536f57c9ab9e1ae74bb02fa21943
shapes-turntable-spp4 frame_0000.png 6454a605ad045b4e184ac439ff90e269be9871620e7aaea9161de4c56b665fbb
shapes-turntable-spp4 frame_0001.exr 16fbd3d37e9bedb1eef71987efebc76f40dd1e3d247f000b143aee17b70e6141
shapes-turntable-spp4 frame_0001.png dad080f07d2049fc6f93c05d4713d4b7b83864a21eb9954ac611eb793a5e80c4
shapes-turntable-spp4 lights.json 5cf7fe6c2b49d21ac4ef6a534666f9447c2078055f30359c36e47887de596a74
shapes-turntable-spp4 stats.csv a461338fc47816d014a8a4192060307042e450eb0fc13570b2175a2b63398fe4
bunny-none frame_0000.exr 72ee95cc342ce2fab26623e951568676dcc27cd8886c50ed9343b6e8a14bc5da
bunny-none frame_0000.png 90224d98d7c01fa1e59296b0a0202cd09b996efb419d64c4633cf9f6e583c99f
bunny-none frame_0001.exr c0e6ec8e17b15c83ec2cce2bfe8e3b0aca9ce2aa609943364b6eb2cd193e1db9
bunny-none frame_0001.png 23465a63b5a16e9b5e5d35127ec048636076bba73519931b0367a450901140e2
bunny-none lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-none stats.csv f81d6fe21e7305425deef527fa8b936ee80aa86cbb74e321678e5bc73fda57e5
bunny-brute frame_0000.exr 27cf54d1a0e9671cc8639a2a6445750c2daf22410dcf9872a1ff9537a1314b09
bunny-brute frame_0000.png f11866cc5a9c02b366e51592f6a712a6faca90d5fd669e00d53cbaa4191ebb95
bunny-brute frame_0001.exr 628c9dc3dc852871fc20bab8b1ab71545c18d6768c0a98054f405279b0c5020a
bunny-brute frame_0001.png 22b820a68cfae71f6b2fdce67f86bb36db9af282eb0b4e8155c6ccbf00900c4b
bunny-brute lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-brute stats.csv ecbe98428374ccf54efba77e17cae9f777d3bd21f98341a50f148580a3e62e5a
bunny-scan-warp-boundary frame_0000.exr 8e39fc1fe610745e5354e0a4e7309b63efc6195a9f9fae82eacc7660c57c7825
bunny-scan-warp-boundary frame_0000.png a8caea0a84a205c19d0b90716040f2e1058cbfc6025c27b0e95b4d866002dfb9
bunny-scan-warp-boundary frame_0001.exr d2fab463cd35149b4b787012fc438ce2a825bf39a8df07063c56060b4109b210
bunny-scan-warp-boundary frame_0001.png 4d70f35d0ba90fa3426fb165ff0ab6ebfcbe06fa74b9bcc1e579195a49c26c9b
bunny-scan-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-warp-boundary stats.csv 4cd9cc6b13f2ded9634b79d422f02501a8b582a09860a6b3370cf40be86ceeba
bunny-grid-warp-boundary frame_0000.exr 7a96e6f8e4930cb3eb221ae87087c75122b6e994cd38895540615cf4aa3c6255
bunny-grid-warp-boundary frame_0000.png fdb619a9f5e1b7f4c5f3a7c626aad8c90b82bc80d2ad10b4cfd67f0af1055976
bunny-grid-warp-boundary frame_0001.exr aa52a90fcaa8bf6aae62c2e72ee8f149911540f72c6081138afaa9abd93edfbc
bunny-grid-warp-boundary frame_0001.png 928e5ad17da31df81fa642ea67200303dc5498b30c793990c0771b52a144b662
bunny-grid-warp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-boundary stats.csv 97e04c6866e8dd8694211fbb8d2e9b720d24584ccfe5d4377d4e366681b12468
bunny-grid-nowarp-boundary frame_0000.exr 063e38b03d277f141f1ed170b2352e5bbb737def5c9874969fe6df277983b228
bunny-grid-nowarp-boundary frame_0000.png d173a46bf311b7fe07240aaa463135de4d657d85b9067b6c3bb75cb566d2a915
bunny-grid-nowarp-boundary frame_0001.exr 62fd29d2a4e05d8d5c9c4b128b6f43f4fc1a21e0f371f9fb6715d145b6746e22
bunny-grid-nowarp-boundary frame_0001.png c4bcbb47da44d98fd1d7a97a215a89a73b06111418ded42b6562321176a98abb
bunny-grid-nowarp-boundary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-boundary stats.csv 612ebc90dc614681249b37f39420459e276755192b94e9f0e0b37f7b484ce1f4
bunny-grid-warp-uncertainty frame_0000.exr d1c98f66c395defbe91cce53b839b4e0154a0bb95dad93be71c02f357d18e64e
bunny-grid-warp-uncertainty frame_0000.png aa4e8dc090b22a945a30f55d622adf41dca74bc10c423ce7cf512d0b57094f09
bunny-grid-warp-uncertainty frame_0001.exr 961e30e2a8656b288c92a05036bf08ec00f77ee45cb23ed21aac6a4213de5f6f
bunny-grid-warp-uncertainty frame_0001.png 31b4b0cfcc410638c51361d8d218a071600160c6f5fb09d2671df5288698113c
bunny-grid-warp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-warp-uncertainty stats.csv d402df74180fca4275edd5b0db7babf8f4b3aea1d18a668e38c8b7acdf8a18d0
bunny-grid-nowarp-uncertainty frame_0000.exr f775af3ed1f4fba8dea79c3de9902fbc687033ac42a8be3abd9a05407ffdb420
bunny-grid-nowarp-uncertainty frame_0000.png 13f63fb0ec664e1f43a74326d0ba4b73faa0f89bae19b51139aedff55db17a9d
bunny-grid-nowarp-uncertainty frame_0001.exr f7919d5ca1c49bf387165ede6137b6f0473e63dd7fcb32cc7d43a2f22082c749
bunny-grid-nowarp-uncertainty frame_0001.png 3ae678bdb2663dcce90d902932e42946944dfb8032fd1e864501141e1be511a1
bunny-grid-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-grid-nowarp-uncertainty stats.csv d97cdfa6cbd4d162b098af7526749b15fbd325a6d182d1db33e06d5c68536d73
bunny-scan-nowarp-uncertainty frame_0000.exr efdfcfb9659e0c5b06bb7c81ffa091ab08d649eb9e07c20211591a773686c332
bunny-scan-nowarp-uncertainty frame_0000.png 2e9dfa02c53bd9c18ca2f1dd2d766769d0041ceaebf622fca636faa55a69efeb
bunny-scan-nowarp-uncertainty frame_0001.exr cddd7c5347f54426af3312ecc373c7830706ad3a7374811909360d45ad0ef525
bunny-scan-nowarp-uncertainty frame_0001.png bd9211bb863ff0be8802aed38ee5aafae9c26328a978289f80d422c03d81c4c0
bunny-scan-nowarp-uncertainty lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-nowarp-uncertainty stats.csv e46a718c4415ec23a5c8eb5a5c7825803beab14dced60b6594448921bcb79784
bunny-nowarp-all frame_0000.exr 68e378e394b60a2b913c0d6d82570ff13d241b01d5ee8e5806fdb2c11e0be74a
bunny-nowarp-all frame_0000.png 3523eb4672fff7ba8d97c469973b7d941acaa4735050938c0933dc5652f11ef7
bunny-nowarp-all frame_0001.exr 69d99e30a456eccd59bec270ac2bc289bee4c4909dc2f4962550c1948b704066
bunny-nowarp-all frame_0001.png 618c210e7611b79fabd3ab3dd3f86c5b675590fea9ca8d9b44b6b305779a6db3
bunny-nowarp-all lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-all stats.csv afe99ace68ccbc889cc0e19697ca65b34b6e0f8e50c7547023bd62cc7724f76b
bunny-nowarp-contrary frame_0000.exr 1e6e7bc7edab531f33fb55a53904f32893cabe261db02e52d9a2d168adfd2758
bunny-nowarp-contrary frame_0000.png 6858368e24c92fd9614adf7ffac27a5dbbb54f0607093c863cc0a1f2ead12e51
bunny-nowarp-contrary frame_0001.exr e89c4190138208e4d76663bcb230e02d9465c9e75b4f39d969bdc92a1231570f
bunny-nowarp-contrary frame_0001.png 659886c0328523978735b50bc84bca782cae18db7bf81ea675708b7121beb74a
bunny-nowarp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-nowarp-contrary stats.csv 01ba11c9bc1fe265c82af411ccc0f0226c0c0b914867e8a6c9de6dc0b8826621
bunny-warp-contrary frame_0000.exr 16d14359e6ea00894d4a69fe9e6e213701c38c7ff072dee49e6abfa20743b6af
bunny-warp-contrary frame_0000.png 68dd503ea7f9d35fe2248a0a250408c01c700f6d556570a4389b3fde2035b2f3
bunny-warp-contrary frame_0001.exr 4d59135a24ffe882443a572c48140f98ca96613e8d634f665d62a9f84d8fb433
bunny-warp-contrary frame_0001.png 7545cad5da1c9d5a147a19b51ef44a996279ee92ccade97eae0093b089597183
bunny-warp-contrary lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-warp-contrary stats.csv 1fd8ed668e40ebf2da8dbfb7bdf450590371147d72a6540ee366c5bae0c8c072
bunny-tuned frame_0001.exr 21221e02e9f69134f08b6c71246b5a7a8ecb5fb8e22c657584dff98cdab83614
bunny-tuned frame_0001.png c0af4f491c5cf40cb87b94918f7482323f2b076b8a50eb9fa1610a786ebb9849
bunny-tuned lights.json f7dd94f909deb0f100b9dbfd34fb72d29f04f800af100ca2098df3f30729369f
bunny-tuned stats.csv 16d6ee2a9cb79117e6c079f163396476741468930dadf082b81da78835bf454b
bunny-scan-block frame_0001.exr 9ba14bf6d03d1b2e31ac8c72094a3e536c165dc0c5281716adeb1858ad1f91d1
bunny-scan-block frame_0001.png deaf3ca82f2e644a0552c7f04d0fa70adf889df53de42a5d2efa0ea22cb2e473
bunny-scan-block lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-scan-block stats.csv 8c89adc2c0019838b4961c03e5dfddf62940fa4d7ba8066a821f98134319170f
bunny-validate frame_0000.exr bbdd0c5a454902254562794c746c0892d564ef0e680b316e00b57065fc392dae
bunny-validate frame_0000.png 13f63fb0ec664e1f43a74326d0ba4b73faa0f89bae19b51139aedff55db17a9d
bunny-validate frame_0001.exr 29275d6c13c679ef4f6464d11f6927aa68cc7e006bdd42402560aca8549c401b
bunny-validate frame_0001.png 3ae678bdb2663dcce90d902932e42946944dfb8032fd1e864501141e1be511a1
bunny-validate lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate stats.csv cf38558c46032e06cd6ac69125eb9d690a625b0251ffb4ad778650cbf1ddc21d
bunny-validate-warp frame_0001.exr 93599d812e9129ac8fc945587fdd1b490a9ecc574a8f1b1fb2426a8fa9ebfde7
bunny-validate-warp frame_0001.png 928e5ad17da31df81fa642ea67200303dc5498b30c793990c0771b52a144b662
bunny-validate-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-warp stats.csv 005447fdcad2a8a392b949a9c1420f77f7f65abcd1d20a45465c718ff5950900
bunny-validate-scan frame_0001.exr b11d9c89a0aac92693140b59cc9c20b2afe3f9088ccda2d8dae8163a8ef8ab59
bunny-validate-scan frame_0001.png 4d70f35d0ba90fa3426fb165ff0ab6ebfcbe06fa74b9bcc1e579195a49c26c9b
bunny-validate-scan lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-validate-scan stats.csv 31c052809af24ff3ae978ee78d387f5e3573c069e215a3f86fd87b8d0de41fcd
bunny-temporal-orbit frame_0002.exr 4d45ccb4f5bf1af4f61e7ffa4baf711ecb74fd95d66b82589da72409193d91b0
bunny-temporal-orbit frame_0002.png 267765cf68e0df57620afddf1e5af00f203b90f8e8b2e905a552530eab9942f9
bunny-temporal-orbit frame_0003.exr e19a30218b8dd7b73480003c97264c70ea622d20d0e87458e0591c58f41fb1e6
bunny-temporal-orbit frame_0003.png c00e0f81a6e978216c1b3093a7dbb82e09ae977b1cc959d87d7678ae365776af
bunny-temporal-orbit frame_0004.exr 9a1f681bd168610102c25136292ab2d61275227743485dd5f0510be905b98498
bunny-temporal-orbit frame_0004.png 452b61f113a3171595026089f3ced024829fb4731ec201242a22272ec9fc70b7
bunny-temporal-orbit frame_0005.exr 231d328bce555763eaf284d15a575b09aa228e4b72ee289f30afb92885fadc9c
bunny-temporal-orbit frame_0005.png 62c5bad3d30b90a79f7edb36c529d880728bcfd4f7245d8cba2ad02acebbadd9
bunny-temporal-orbit lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-orbit stats.csv b276a8209031874950629ba15edcef05bdb3df3cc9940acc6493a9a5beb92b67
bunny-temporal-warp frame_0000.exr d1c98f66c395defbe91cce53b839b4e0154a0bb95dad93be71c02f357d18e64e
bunny-temporal-warp frame_0000.png aa4e8dc090b22a945a30f55d622adf41dca74bc10c423ce7cf512d0b57094f09
bunny-temporal-warp frame_0001.exr 62fd164ea7e639ff85fc84ce93d8501b32b1201dd39a0eb490724884c3535233
bunny-temporal-warp frame_0001.png 81c7f26a05a00d7542999a22a494b3d9ef3c8e3728bd7eb48cee8e9b891990ad
bunny-temporal-warp frame_0002.exr e73554ba0ab2499e1d6634092f65a39d1df64f6823f0a4d8de0880ea97b93938
bunny-temporal-warp frame_0002.png 0c6950a803d186e61ce931ccbb5688dfb1cd8d589284f236c3e1746fa331fbe3
bunny-temporal-warp lights.json c9783aa9a6641edc30d129c59f46519eb054a7a73fcb76955bf0c34d7e4435a1
bunny-temporal-warp stats.csv e1e60e74ecd78045ab215143b5f1bf6ba7b6aff54f068207d24675fa73495f86
bunny-temporal-spin frame_0000.exr 75b2fd611a7cad52e82bfcf481d87c0ebb67fe380f156dcaedabb7a808d50657
bunny-temporal-spin frame_0000.png b7ef9a783408f367bbefc12d984af47716999bc1c88258b037f74dfed40b4a82
bunny-temporal-spin frame_0001.exr 7747cf62bdfc3fc100817fef600c2c8dc8a163d903d631da3d6564c25c925c6a
bunny-temporal-spin frame_0001.png 07f3123325bfbcbcc5c9b4ea7ac4472d0adff5d6567339d1e27af5b508eeb37d
bunny-temporal-spin frame_0002.exr 7ea94ded6f2ba3af552e5b3af3bb49a43fc06ab6296f97261ea08174ee65f580
bunny-temporal-spin frame_0002.png 127a74d0bd3058291e0189c653889187c90e0e657f4f6cd3a31006294a621c17
bunny-temporal-spin frame_0003.exr f36aef890e0620155b91d165319f9a9086a6a7e54f1be6bddba273be8a94fa73
bunny-temporal-spin frame_0003.png 2f9cab4a16d26546c4955fbf00d5edf10bec3cc2e05cbe793b05c883aefccb53
bunny-temporal-spin lights.json 103f720aa426b7ad9ed05f0b47b0a7d9096a5429b996d950aa4e62c981aa7cd5
bunny-temporal-spin stats.csv 59e256b4742bd03f29b27b65c6435d92623a50d95dfd85f53fc5b4e16561a705
";

fn sha(bytes: &[u8]) -> String {
    format!("{:x}", Sha256::digest(bytes))
}

/// `stats.csv` with the `thread_seconds` column emptied and the last column, `spp`, removed once
/// checked to be `spp` everywhere.
fn stats_without_seconds(text: &str, spp: &str) -> String {
    let mut lines = text.lines();
    let mut header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == "thread_seconds")
        .expect("stats.csv has a thread_seconds column");
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
