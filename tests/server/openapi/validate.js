// validate.js FILE — validate an OpenAPI 3.1 document with
// @apidevtools/swagger-parser (schema + $ref resolution); print one line per
// check as "ok NAME" / "FAIL NAME: why".
const SwaggerParser = require("@apidevtools/swagger-parser");
const file = process.argv[2];
(async () => {
  let failed = 0;
  try {
    const api = await SwaggerParser.validate(file);
    console.log(`ok validate: ${api.info.title} ${api.info.version}, OpenAPI ${api.openapi}, ` +
                `${Object.keys(api.paths).length} paths`);
  } catch (e) {
    console.log(`FAIL validate: ${e.message}`);
    failed++;
  }
  try {
    const api = await SwaggerParser.dereference(file);
    const ids = new Set();
    for (const [p, item] of Object.entries(api.paths))
      for (const [m, op] of Object.entries(item)) {
        if (typeof op !== "object" || !op.operationId) continue;
        if (ids.has(op.operationId)) throw new Error(`duplicate operationId ${op.operationId}`);
        ids.add(op.operationId);
      }
    console.log(`ok operation ids unique (${ids.size})`);
  } catch (e) {
    console.log(`FAIL operation ids: ${e.message}`);
    failed++;
  }
  process.exit(failed ? 1 : 0);
})();
